//! Fuzz target: any bytes as a table file, parsed and analysed under the
//! budgets exactly as `symlab check` does. A panic, a stack overflow, a
//! timeout (libFuzzer's `-timeout`) or an allocation beyond `-rss_limit_mb`
//! is a finding; an `Err` with a message is the expected answer to bad input.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tableau::algebraic::file::{Loaded, parse};
use tableau::analysis::{self, Analysis};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match parse("fuzz.toml", text) {
        Err(e) => assert!(!e.to_string().is_empty()),
        Ok(Loaded::Classic(tf)) => {
            if let Ok(an) = Analysis::of(&tf.table) {
                for c in &tf.claims {
                    let _ = analysis::check_claim(&tf.table, &an, c);
                }
            }
        }
        Ok(Loaded::Generated(g)) => {
            // Generating checks every claim; check one again as a reader would.
            if let Some((c, _)) = g.claims.first() {
                let _ = g.check_claim(c);
            }
        }
        Ok(Loaded::Algebraic(f)) => {
            let an = f.analyse();
            for c in &f.claims {
                let _ = f.check_claim(&an, c);
            }
        }
    }
});
