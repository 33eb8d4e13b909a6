//! Tests of `compare::guard` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::guard::*;
use compare::*;
#[test]
fn a_panic_becomes_its_message_and_the_thread_goes_on() {
    let r: Result<(), String> = catch(|| panic!("bad step {}", 3));
    assert_eq!(r.unwrap_err(), "bad step 3");
    assert_eq!(catch(|| 5).unwrap(), 5);
    let r: Result<(), String> = catch(|| std::panic::panic_any(7u8));
    assert_eq!(r.unwrap_err(), "a panic without a message");
}
