//! "What the paper claims": its sentences, quoted.

use std::fmt::Write as _;

/// The paper's claims about the oscillator, in its words.
const CLAIMS: [&str; 5] = [
    "Abstract: the symplectic algorithms \"can preserve the system energy constant and can give the exact \
     results even at large time-step, however the ordinary non-symplectic explicit method exhibit large error \
     with the increasing of time-step\".",
    "Figure 2 (the 2-stage semi-implicit symplectic RK at h = 0.05): \"the amplitudes of the displacement \
     and velocity keep constant\".",
    "At h = 0.01 \"the former three methods are able to get the right results in short term simulation, but \
     the fourth one still gives the results with large error\".",
    "Figures 2 and 3: \"when the computation step 0.1s is adopted, after 200 steps, only the symplectic \
     algorithms can carry out the right simulation, but the results from the other nonsymplectic methods are \
     unable to be convergent to the analytical results\".",
    "Figure 4: \"The errors from symplectic schemes are far smaller than that of Heun-Runge-Kutta scheme\"; \
     \"The higher the order is, the higher the precision is.\"",
];

pub(super) fn write(w: &mut String) {
    let _ = writeln!(w, "## What the paper claims\n");
    for claim in CLAIMS {
        let _ = writeln!(w, "- {claim}");
    }
    let _ = writeln!(w);
}
