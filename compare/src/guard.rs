//! User code runs inside the experiments — a `Step` of your own, a
//! `Problem` of your own — and a panic there must not take a whole sweep
//! down: each run is wrapped in [`catch`], and a run that panicked becomes a
//! row whose `status` is `panicked at step k: <message>` (or `panicked
//! before the first step: …`; [`Status::Panicked`](crate::Status)), while
//! the sweep goes on.
//!
//! The default panic hook would still print the message and a backtrace
//! hint on stderr for every caught panic; [`catch`] installs, once, a hook
//! that stays silent while the current thread is inside [`catch`] and hands
//! every other panic to the hook that was there before.

use std::cell::Cell;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Once;

thread_local! {
    static CATCHING: Cell<u32> = const { Cell::new(0) };
}

static HOOK: Once = Once::new();

fn install_hook() {
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if CATCHING.with(Cell::get) == 0 {
                previous(info);
            }
        }));
    });
}

/// The message of a panic payload (`panic!("…")` gives a `&str` or a
/// `String`; anything else is named as such).
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic without a message".to_string()
    }
}

/// Run `f`; a panic inside it is returned as its message instead of
/// unwinding further, and is not printed.
pub fn catch<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    install_hook();
    CATCHING.with(|c| c.set(c.get() + 1));
    let out = catch_unwind(AssertUnwindSafe(f));
    CATCHING.with(|c| c.set(c.get() - 1));
    out.map_err(|p| one_line(&panic_message(&*p)))
}

/// A message on one line (it goes into a CSV cell and a report table).
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}
