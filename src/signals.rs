//! SIGINT and SIGTERM end a long run cleanly: the handler only records the
//! signal in an atomic that the run polls between frames (or sweep rows),
//! so the run writes its frames so far, a checkpoint and the summary of
//! what ran, then exits with 128 + the signal (130 for SIGINT, 143 for
//! SIGTERM), as a shell reports a process the signal ended. A second
//! signal exits at once, with the same status: a run stuck in one long
//! step can still be stopped.
//!
//! Installed only by the commands that poll it (`cloth`, `compare`,
//! `resume`): elsewhere Ctrl-C keeps its default, immediate effect.

use std::sync::atomic::{AtomicI32, Ordering};

/// The first signal received (0: none).
static RECEIVED: AtomicI32 = AtomicI32::new(0);

#[cfg(unix)]
extern "C" fn on_signal(sig: libc::c_int) {
    // Only async-signal-safe work here: an atomic swap and `_exit`.
    if RECEIVED.swap(sig, Ordering::SeqCst) != 0 {
        // SAFETY: `_exit` is async-signal-safe and ends the process.
        unsafe { libc::_exit(128 + sig) }
    }
}

/// Install the handlers for SIGINT and SIGTERM.
pub fn install() {
    #[cfg(unix)]
    // SAFETY: `on_signal` is an `extern "C" fn(c_int)` that does only
    // async-signal-safe work; installing it replaces the default action.
    unsafe {
        let handler = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
        libc::signal(libc::SIGINT, handler);
        libc::signal(libc::SIGTERM, handler);
    }
}

/// The signal that asked the run to stop, if one did.
pub fn requested() -> Option<i32> {
    match RECEIVED.load(Ordering::SeqCst) {
        0 => None,
        sig => Some(sig),
    }
}

/// The signal's name for messages.
pub fn name(sig: i32) -> &'static str {
    match sig {
        2 => "SIGINT",
        15 => "SIGTERM",
        _ => "a signal",
    }
}

/// The exit status of a run the signal stopped: 128 + the signal.
pub fn exit_status(sig: i32) -> u8 {
    u8::try_from(128 + sig).unwrap_or(1)
}
