//! The `vizretarget` binary: parse, run, report. Exit codes: 0 done (also when the reader of
//! stdout went away early), 1 failed (bad input, unwritable output, ...), 2 usage error (from
//! clap, or an option value or combination refused before any work: `cli::UsageError`),
//! 128 + the signal when stopped by SIGINT (130, Ctrl-C) or SIGTERM (143). Every error is
//! one line on stderr.

use clap::Parser;
use std::process::ExitCode;

mod cli;

fn main() -> ExitCode {
    let args = match cli::Cli::try_parse() {
        Ok(args) => args,
        // --help and --version go to stdout, as clap prints them.
        Err(e) if !e.use_stderr() => e.exit(),
        Err(e) => {
            eprintln!("vizretarget: error: {} (see --help)", usage_line(&e));
            return ExitCode::from(e.exit_code().clamp(1, 255) as u8);
        }
    };
    match cli::run(args) {
        Ok(cli::Outcome::Done) => ExitCode::SUCCESS,
        Ok(cli::Outcome::Interrupted) => ExitCode::from(cli::interrupted_exit_code()),
        Err(e) => {
            let hint = cli::limit_hint(&e).map_or_else(String::new, |h| format!("; {h}"));
            eprintln!("vizretarget: error: {}{hint}", chain_line(&e));
            if cli::is_usage_error(&e) {
                ExitCode::from(2)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}

/// The error and its causes, joined by ": ". A cause whose text its parent already shows (the
/// library's `Io` error prints its `io::Error`) is not repeated, as `{e:#}` would.
fn chain_line(e: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if line.ends_with(&text) {
            continue;
        }
        if !line.is_empty() {
            line.push_str(": ");
        }
        line.push_str(&text);
    }
    printable(&line)
}

/// clap's message without its "error: " prefix, usage block and hint, on one line.
fn usage_line(e: &clap::Error) -> String {
    let text = e.render().to_string();
    let text = text.split("\nUsage:").next().unwrap_or_default();
    let mut line = String::new();
    for part in text.lines().map(str::trim) {
        if part.is_empty() || part.starts_with("For more information") {
            continue;
        }
        if !line.is_empty() {
            line.push_str(if part.starts_with("tip:") { "; " } else { " " });
        }
        line.push_str(part);
    }
    printable(line.strip_prefix("error: ").unwrap_or(&line))
}

/// Paths and decoder messages may hold control characters: keep the report on one line.
fn printable(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect()
}
