//! Every command of README.md's `sh` blocks and every example of `--help` (and of `watch
//! --help` and `compare --help`) runs as written, from a clone's files (issue 39): read from
//! the README and from the binary's own help, so neither can drift from what runs. Each runs
//! in a temporary folder laid out as a clone (`streams/`, `out/`, `target/release/`), must
//! exit 0 (a `watch`: 130 after Ctrl-C), and must write each `out/...` it names, of the kind
//! its name says; nothing may land outside `out/`, which the clone's `out/.gitignore` keeps out
//! of git.
//!
//! The commands that pipe through ffmpeg run where ffmpeg is installed (`.ci/run` installs
//! it); without it they are listed as not run, and under CI they fail.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The commands of the README's `sh` blocks: continued lines joined, comments dropped,
/// `cargo run --release --` read as the binary, `cargo test` (this very suite) left out.
fn readme_commands(readme: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut in_block = false;
    let mut lines = Vec::new();
    for line in readme.lines() {
        if line.trim_start().starts_with("```") {
            in_block = !in_block && line.trim() == "```sh";
            continue;
        }
        if in_block {
            lines.push(line.to_string());
        }
    }
    for cmd in joined(&lines) {
        let cmd = cmd.trim();
        if cmd.is_empty() || cmd.starts_with('#') || cmd.starts_with("cargo test") {
            continue;
        }
        out.push(cmd.replace("cargo run --release -- ", "vizretarget "));
    }
    out
}

/// Lines ending in `\` joined with the next.
fn joined(lines: &[String]) -> Vec<String> {
    let mut out = Vec::new();
    let mut current = String::new();
    for line in lines {
        let t = line.trim();
        match t.strip_suffix('\\') {
            Some(head) => {
                current.push_str(head.trim_end());
                current.push(' ');
            }
            None => {
                current.push_str(t);
                out.push(std::mem::take(&mut current));
            }
        }
    }
    out
}

/// The examples of a help text: from its line starting with "Example" on, lines that start
/// with `vizretarget `, `ffmpeg ` or `cat `, joined with their continuation lines.
fn help_commands(help: &str) -> Vec<String> {
    let lines: Vec<String> = help
        .lines()
        .skip_while(|l| !l.starts_with("Example"))
        .map(String::from)
        .collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let t = lines[i].trim_start();
        if t.starts_with("vizretarget ") || t.starts_with("ffmpeg ") || t.starts_with("cat ") {
            let mut block = vec![lines[i].clone()];
            while block.last().unwrap().trim_end().ends_with('\\') && i + 1 < lines.len() {
                i += 1;
                block.push(lines[i].clone());
            }
            out.extend(joined(&block));
        }
        i += 1;
    }
    out
}

fn help(args: &[&str]) -> String {
    let out = common::bin().args(args).output().unwrap();
    assert!(out.status.success(), "{args:?}");
    String::from_utf8(out.stdout).unwrap()
}

/// A folder laid out as a fresh clone: the samples, `out/` as committed, and the binary where
/// `cargo build --release` puts it.
fn clone_like() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(ROOT);
    std::os::unix::fs::symlink(root.join("streams"), dir.path().join("streams")).unwrap();
    std::fs::create_dir(dir.path().join("out")).unwrap();
    std::fs::copy(
        root.join("out/.gitignore"),
        dir.path().join("out/.gitignore"),
    )
    .unwrap();
    std::fs::create_dir_all(dir.path().join("target/release")).unwrap();
    std::os::unix::fs::symlink(
        env!("CARGO_BIN_EXE_vizretarget"),
        dir.path().join("target/release/vizretarget"),
    )
    .unwrap();
    dir
}

/// `sh` running `cmd` in `dir`, with the binary on the PATH as `vizretarget`.
fn shell(dir: &Path, cmd: &str) -> Command {
    let bin_dir = Path::new(env!("CARGO_BIN_EXE_vizretarget"))
        .parent()
        .unwrap();
    let path = format!(
        "{}:{}",
        bin_dir.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut c = Command::new("bash");
    c.args(["-c", &format!("set -eo pipefail; {cmd}")])
        .current_dir(dir)
        .env("PATH", path)
        .stdin(Stdio::null());
    c
}

fn has_ffmpeg() -> bool {
    Command::new("ffmpeg")
        .arg("-version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// The `out/...` paths a command names.
fn outputs(cmd: &str) -> Vec<String> {
    cmd.split_whitespace()
        .map(|t| t.trim_start_matches('>'))
        .filter(|t| t.starts_with("out/"))
        .map(String::from)
        .collect()
}

/// Checks that `path` (under `dir`) holds what its name says; the problem if not.
fn check_kind(dir: &Path, name: &str) -> Result<(), String> {
    let path = dir.join(name);
    if name.ends_with('/') {
        let entries: Vec<PathBuf> = std::fs::read_dir(&path)
            .map_err(|e| format!("{name}: {e}"))?
            .map(|e| e.unwrap().path())
            .collect();
        if !entries
            .iter()
            .any(|p| p.extension().is_some_and(|x| x == "png"))
        {
            return Err(format!("{name}: no PNG in the folder"));
        }
        for p in entries
            .iter()
            .filter(|p| p.extension().is_some_and(|x| x == "png"))
        {
            let rel = p.strip_prefix(dir).unwrap().to_string_lossy().into_owned();
            check_kind(dir, &rel)?;
        }
        return Ok(());
    }
    let bytes = std::fs::read(&path).map_err(|e| format!("{name}: {e}"))?;
    let ext = name.rsplit('.').next().unwrap_or("");
    let ok = match ext {
        "png" => bytes.starts_with(b"\x89PNG\r\n\x1a\n") && image::load_from_memory(&bytes).is_ok(),
        "jpg" | "jpeg" => bytes.starts_with(&[0xFF, 0xD8, 0xFF]),
        "gif" => bytes.starts_with(b"GIF89a") && bytes.ends_with(b";"),
        "webp" => bytes.len() > 12 && &bytes[8..12] == b"WEBP",
        "mp4" => bytes.len() > 8 && &bytes[4..8] == b"ftyp",
        "json" => {
            let t = String::from_utf8_lossy(&bytes);
            t.trim_start().starts_with('{') && t.trim_end().ends_with('}')
        }
        "bash" => String::from_utf8_lossy(&bytes).contains("complete -F"),
        _ => return Err(format!("{name}: no check for this kind of file")),
    };
    if ok {
        Ok(())
    } else {
        Err(format!("{name}: not a {ext} file ({} bytes)", bytes.len()))
    }
}

/// Runs a `watch` command until it has written one output per picture of the folder it
/// watches, then stops it as Ctrl-C does: exit 130.
fn run_watch(dir: &Path, cmd: &str) -> Result<(), String> {
    let words: Vec<&str> = cmd.split_whitespace().collect();
    let watched = words[words.iter().position(|w| *w == "watch").unwrap() + 1];
    let out = words[words.iter().position(|w| *w == "-o").unwrap() + 1];
    let want = std::fs::read_dir(dir.join(watched))
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == "png")
        })
        .count();
    if dir.join(out).exists() {
        return Err(format!(
            "{cmd}: {out} exists already: give each example its own output"
        ));
    }
    let mut child = shell(dir, &format!("exec {cmd}"))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let done = || {
        std::fs::read_dir(dir.join(out))
            .map(|d| {
                d.filter(|e| {
                    !e.as_ref()
                        .unwrap()
                        .file_name()
                        .to_string_lossy()
                        .starts_with('.')
                })
                .count()
            })
            .unwrap_or(0)
    };
    while done() < want && start.elapsed() < Duration::from_secs(120) {
        if let Some(status) = child.try_wait().unwrap() {
            return Err(format!("{cmd}: ended by itself ({status})"));
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
    let status = child.wait().unwrap();
    if done() < want {
        return Err(format!("{cmd}: {} of {want} snapshots written", done()));
    }
    if status.code() != Some(130) {
        return Err(format!("{cmd}: exit {status} after SIGINT, not 130"));
    }
    Ok(())
}

/// Runs each command in a clone-like folder; the problems found, one line each.
fn run_all(commands: &[String]) -> Vec<String> {
    let ffmpeg = has_ffmpeg();
    let dir = clone_like();
    let mut problems = Vec::new();
    for cmd in commands {
        let outs = outputs(cmd);
        if outs.is_empty() && !cmd.contains("-o /dev/null") {
            problems.push(format!("{cmd}: writes nothing into out/"));
            continue;
        }
        if cmd.contains("ffmpeg ") && !ffmpeg {
            if std::env::var_os("CI").is_some() {
                problems.push(format!(
                    "{cmd}: ffmpeg is not installed (.ci/run installs it)"
                ));
            } else {
                eprintln!("not run (no ffmpeg here): {cmd}");
            }
            continue;
        }
        let result = if cmd.contains("vizretarget watch ") {
            run_watch(dir.path(), cmd)
        } else {
            let out = shell(dir.path(), cmd).output().unwrap();
            if out.status.success() {
                Ok(())
            } else {
                Err(format!(
                    "{cmd}: exit {}: {}",
                    out.status,
                    String::from_utf8_lossy(&out.stderr).trim()
                ))
            }
        };
        problems.extend(result.err());
        problems.extend(outs.iter().filter_map(|o| check_kind(dir.path(), o).err()));
    }
    // Nothing beside what a clone has: the outputs all went into out/.
    let mut top: Vec<String> = common::listing(dir.path());
    top.retain(|n| !["out", "streams", "target"].contains(&n.as_str()));
    if !top.is_empty() {
        problems.push(format!("written outside out/: {top:?}"));
    }
    problems
}

#[test]
fn the_readme_commands_are_read_whole() {
    let readme = std::fs::read_to_string(Path::new(ROOT).join("README.md")).unwrap();
    let cmds = readme_commands(&readme);
    // The quick start's first command, and a continued pipeline as one command.
    assert!(
        cmds[0].starts_with("vizretarget streams/scatter-map/frame-0000.png"),
        "{cmds:?}"
    );
    assert!(
        cmds.iter()
            .any(|c| c.starts_with("ffmpeg -i") && c.contains("| ffmpeg -f yuv4mpegpipe")),
        "{cmds:?}"
    );
    assert!(cmds.iter().all(|c| !c.contains('\\')), "{cmds:?}");
    let h = help_commands(
        "vizretarget is a tool\nExamples:\n  vizretarget a.png \\\n      | x\n      What it does\n",
    );
    assert_eq!(h, ["vizretarget a.png | x"]);
}

#[test]
fn every_readme_command_runs_from_a_clone() {
    let readme = std::fs::read_to_string(Path::new(ROOT).join("README.md")).unwrap();
    let cmds = readme_commands(&readme);
    assert!(cmds.len() >= 15, "{cmds:#?}");
    let problems = run_all(&cmds);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn every_help_example_runs_from_a_clone() {
    let mut cmds = help_commands(&help(&["--help"]));
    assert!(cmds.len() >= 14, "{cmds:#?}");
    cmds.extend(help_commands(&help(&["watch", "--help"])));
    cmds.extend(help_commands(&help(&["compare", "--help"])));
    let problems = run_all(&cmds);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The clone's `out/` is in git (its `.gitignore`) and ignores everything else in it.
#[test]
fn out_is_kept_out_of_git() {
    let ignore = std::fs::read_to_string(Path::new(ROOT).join("out/.gitignore")).unwrap();
    let rules: Vec<&str> = ignore
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .collect();
    assert_eq!(rules, ["*", "!.gitignore"]);
}
