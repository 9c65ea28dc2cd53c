//! SIGINT (Ctrl-C) and SIGTERM (`kill`, a service manager stopping the program).
//!
//! Installed at the start of every run ([`install`]). Until a stream run reaches the point
//! where it can stop cleanly ([`stop_gracefully`]), a signal removes the temporary files of
//! unfinished outputs and exits at once with 128 + the signal's number: nothing was written
//! yet, and the input may be a pipe that blocks. From then on the first signal only sets the
//! cancel flag: the pipeline finishes the frames in flight, the sink completes its output,
//! and the run exits with 128 + that signal (130 for SIGINT, 143 for SIGTERM). A second
//! signal removes the unfinished temporary files and exits at once, with 128 + its number.

use anyhow::{Context, Result};
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::{Arc, OnceLock};

struct State {
    cancel: Arc<AtomicBool>,
    /// The first signal received (0: none).
    first: AtomicI32,
    /// Whether a signal asks the run to finish what it started rather than exit at once.
    graceful: AtomicBool,
}

static STATE: OnceLock<State> = OnceLock::new();

fn state() -> &'static State {
    STATE.get_or_init(|| State {
        cancel: Arc::new(AtomicBool::new(false)),
        first: AtomicI32::new(0),
        graceful: AtomicBool::new(false),
    })
}

const SIGINT: i32 = 2;

/// What a signal does, on the thread that receives it (not in the signal handler).
fn on_signal(sig: i32) {
    let s = state();
    let stop_now = !s.graceful.load(Ordering::SeqCst)
        || s.first
            .compare_exchange(0, sig, Ordering::SeqCst, Ordering::SeqCst)
            .is_err();
    if stop_now {
        vizretarget::io::remove_temporary_files();
        // Said, so that a log shows why the run ended without its summary line.
        eprintln!(
            "vizretarget: {}: stopped at once; unfinished outputs removed",
            name(sig)
        );
        std::process::exit(128 + sig);
    }
    s.cancel.store(true, Ordering::SeqCst);
    eprintln!(
        "vizretarget: {}: finishing the frames in flight and completing the output ({} again \
         to quit at once)",
        name(sig),
        if sig == SIGINT { "Ctrl-C" } else { "signal" }
    );
}

fn name(sig: i32) -> &'static str {
    match sig {
        2 => "interrupted (SIGINT)",
        15 => "terminated (SIGTERM)",
        _ => "stopped by a signal",
    }
}

/// Installs the handler of SIGINT and SIGTERM (once per process).
pub fn install() -> Result<()> {
    static INSTALLED: OnceLock<()> = OnceLock::new();
    if INSTALLED.get().is_some() {
        return Ok(());
    }
    state();
    #[cfg(unix)]
    {
        use signal_hook::consts::{SIGINT, SIGTERM};
        let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM])
            .context("cannot install the handler of SIGINT and SIGTERM")?;
        std::thread::Builder::new()
            .name("signals".into())
            .spawn(move || {
                for sig in signals.forever() {
                    on_signal(sig);
                }
            })
            .context("cannot start the signal thread")?;
    }
    #[cfg(not(unix))]
    ctrlc::set_handler(|| on_signal(SIGINT)).context("cannot install the Ctrl-C handler")?;
    let _ = INSTALLED.set(());
    Ok(())
}

/// The process's cancel flag. From this call on, a first signal sets it (the run finishes the
/// frames in flight and completes its output) instead of ending the process at once.
pub fn stop_gracefully() -> Arc<AtomicBool> {
    let s = state();
    s.graceful.store(true, Ordering::SeqCst);
    s.cancel.clone()
}

/// Whether a signal asked the run to stop.
pub fn interrupted() -> bool {
    state().cancel.load(Ordering::SeqCst)
}

/// The exit code of a run stopped by a signal: 128 + its number (130 if none was recorded).
pub fn exit_code() -> u8 {
    match state().first.load(Ordering::SeqCst) {
        sig @ 1..=127 => 128 + sig as u8,
        _ => 130,
    }
}
