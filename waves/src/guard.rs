//! Runs third-party parsing code so that a panic in it becomes an error value
//! and prints nothing.
//!
//! [`crate::validate`] is meant to refuse every file `wellen` panics on; this
//! guard is the second line of defence. `catch_unwind` alone would still let
//! the default panic hook print "thread 'main' panicked at ..." (and a
//! backtrace) before unwinding, so the first call installs a panic hook that
//! stays silent on threads currently inside [`quietly`] and hands every other
//! panic to the hook that was installed before it (unchanged behaviour for the
//! rest of the program).

use std::cell::{Cell, RefCell};
use std::panic::{self, AssertUnwindSafe};
use std::sync::Once;

thread_local! {
    static QUIET: Cell<bool> = const { Cell::new(false) };
    static LAST: RefCell<Option<String>> = const { RefCell::new(None) };
}

static HOOK: Once = Once::new();

fn payload_text(p: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".to_string()
    }
}

/// Runs `f`; a panic inside it is returned as `Err(message)` (with its source
/// location) and nothing is printed.
pub(crate) fn quietly<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    HOOK.call_once(|| {
        let previous = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            if QUIET.with(Cell::get) {
                let at = info
                    .location()
                    .map(|l| format!(" at {}:{}", l.file(), l.line()))
                    .unwrap_or_default();
                let msg = format!("{}{at}", payload_text(info.payload()));
                LAST.with(|l| *l.borrow_mut() = Some(msg));
            } else {
                previous(info);
            }
        }));
    });
    let was = QUIET.with(|q| q.replace(true));
    let r = panic::catch_unwind(AssertUnwindSafe(f));
    QUIET.with(|q| q.set(was));
    r.map_err(|p| {
        LAST.with(|l| l.borrow_mut().take())
            .unwrap_or_else(|| payload_text(p.as_ref()))
    })
}

#[cfg(test)]
mod tests {
    use super::quietly;

    #[test]
    fn a_panic_becomes_its_message_and_other_results_pass_through() {
        assert_eq!(quietly(|| 7), Ok(7));
        let e = quietly(|| -> u8 { panic!("bad bit {}", 2) }).unwrap_err();
        assert!(e.starts_with("bad bit 2 at "), "{e}");
        assert!(e.contains("guard.rs"), "{e}");
        // nested use restores the outer state
        let outer = quietly(|| {
            let inner = quietly(|| -> u8 { panic!("inner") });
            assert!(inner.unwrap_err().starts_with("inner"));
            panic!("outer")
        });
        assert!(outer.unwrap_err().starts_with("outer"));
    }
}
