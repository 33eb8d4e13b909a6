//! Fuzz target: any bytes as a table file, parsed and analysed under the
//! budgets exactly as `symlab check` does. A panic, a stack overflow, a
//! timeout (libFuzzer's `-timeout`) or an allocation beyond `-rss_limit_mb`
//! is a finding; an `Err` with a message is the expected answer to bad input.
//! Classic files go through the near-integrable and processed readers too
//! (`order = (P1, …)` claims, `kernel` + `corrector_*`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use tableau::algebraic::file::{Loaded, parse};
use tableau::analysis::{self, Analysis};
use tableau::near_integrable;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match parse("fuzz.toml", text) {
        Err(e) => assert!(!e.to_string().is_empty()),
        Ok(Loaded::Classic(tf)) => {
            if let Ok(an) = Analysis::of(&tf.table) {
                // As `symlab check` and `compare --table` decide them: a
                // processed file's claims are its effective method's.
                for c in &tf.claims {
                    let _ = analysis::check_file_claim(&tf, &an, c);
                }
            }
            // The generalised orders `check` reports for a drift–kick
            // sequence or composition (near-integrable files), and the
            // effective ones of a kernel with a corrector (processed files).
            match tf.corrector_table() {
                Some(chi) => {
                    let _ = near_integrable::processed_orders(&tf.table, &chi, &[12, 4, 4, 4], None);
                }
                None => {
                    let _ = near_integrable::near_orders(&tf.table, &near_integrable::REPORT_DEGREES, None);
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
