//! Ctrl-C: the first sets the cancel flag (the pipeline finishes the frames in flight and the
//! sink completes its file; exit 130), a second removes unfinished temporary files and exits
//! at once with 130.

use anyhow::{Context, Result};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();

/// The process's cancel flag, with the Ctrl-C handler installed on first use.
pub fn cancel_flag() -> Result<Arc<AtomicBool>> {
    if let Some(f) = FLAG.get() {
        return Ok(f.clone());
    }
    let flag = Arc::new(AtomicBool::new(false));
    let for_handler = flag.clone();
    ctrlc::set_handler(move || {
        if for_handler.swap(true, Ordering::SeqCst) {
            vizretarget::io::remove_temporary_files();
            std::process::exit(130);
        }
        eprintln!("vizretarget: stopping after the frames in flight (Ctrl-C again to quit now)");
    })
    .context("cannot install the Ctrl-C handler")?;
    let _ = FLAG.set(flag.clone());
    Ok(flag)
}
