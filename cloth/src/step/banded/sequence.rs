//! The drift–kick sequence a banded step applies, by method id.

use integrator_core::interp::SplittingInterpreter;

/// A drift `q += h·c·M⁻¹p` or a kick `p += h·c·F(q)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    Drift,
    Kick,
}

/// One step as flows with their coefficients (zeros dropped), each applied
/// with compensated summation as the library's split steps apply them.
#[derive(Clone, Debug, PartialEq)]
pub struct Sequence {
    flows: Vec<(Flow, f64)>,
    /// The first and the last flow are kicks: a step's first force is the
    /// previous step's last (first same as last).
    reuse_force: bool,
}

impl Sequence {
    /// The sequence of the explicit method `id`, or `None` where it is no
    /// sequence of plain drifts and kicks (Runge–Kutta tables, implicit
    /// ones, gradient kicks).
    ///
    /// Library drift–kick sequences and compositions of Störmer–Verlet
    /// (`leapfrog`, `forest-ruth`, …) come from the catalogue through
    /// [`SplittingInterpreter`], which rounds the coefficients exactly as
    /// `butcher!` does for the scheme's own step: the banded step then
    /// applies the same flows with the same arithmetic as
    /// [`SchemeStepper`](crate::step::SchemeStepper), and its trajectory
    /// is the same to the bit (tested). The three explicit partitioned
    /// pairs are written out: `symplectic-euler-a` (`â = 1`: p first) is a
    /// kick then a drift, `symplectic-euler-b` a drift then a kick,
    /// `stormer-verlet` (Lobatto IIIA–IIIB) kick ½, drift 1, kick ½. Their
    /// own steps form the stage values without the carried rounding errors
    /// and update `p` once from both forces, so they agree with these
    /// sequences to round-off, not to the bit (tested).
    pub fn of(id: &str) -> Option<Sequence> {
        use Flow::{Drift, Kick};
        let flows = match id {
            "symplectic-euler-a" => vec![(Kick, 1.0), (Drift, 1.0)],
            "symplectic-euler-b" => vec![(Drift, 1.0), (Kick, 1.0)],
            "stormer-verlet" => vec![(Kick, 0.5), (Drift, 1.0), (Kick, 0.5)],
            _ => {
                let it = SplittingInterpreter::from_catalogue(id).ok()?;
                let (drift, kick) = (it.drift(), it.kick());
                // One more kick than drifts: the sequence starts with one.
                let kick_first = kick.len() == drift.len() + 1;
                let (first, second, kind) = if kick_first {
                    (kick, drift, (Kick, Drift))
                } else {
                    (drift, kick, (Drift, Kick))
                };
                (0..first.len().max(second.len()))
                    .flat_map(|i| {
                        let a = first.get(i).map(|&c| (kind.0, c));
                        let b = second.get(i).map(|&c| (kind.1, c));
                        a.into_iter().chain(b)
                    })
                    .collect()
            }
        };
        Some(Sequence::new(flows))
    }

    /// `flows` in order (zero coefficients dropped).
    pub fn new(flows: Vec<(Flow, f64)>) -> Sequence {
        let flows: Vec<(Flow, f64)> = flows.into_iter().filter(|f| f.1 != 0.0).collect();
        let reuse_force = flows.len() > 1
            && flows.first().map(|f| f.0) == Some(Flow::Kick)
            && flows.last().map(|f| f.0) == Some(Flow::Kick);
        Sequence { flows, reuse_force }
    }

    pub fn flows(&self) -> &[(Flow, f64)] {
        &self.flows
    }

    /// Whether a step after another starts with the force the last one
    /// ended with.
    pub fn reuses_force(&self) -> bool {
        self.reuse_force
    }

    /// Force evaluations per step, the first one reused where it can be.
    pub fn forces(&self) -> usize {
        let kicks = self.flows.iter().filter(|f| f.0 == Flow::Kick).count();
        kicks - usize::from(self.reuse_force)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sequences_of_the_library() {
        use Flow::{Drift, Kick};
        let lf = Sequence::of("leapfrog").unwrap();
        assert_eq!(lf.flows(), &[(Drift, 0.5), (Kick, 1.0), (Drift, 0.5)]);
        assert!(!lf.reuses_force());
        let sv = Sequence::of("stormer-verlet").unwrap();
        assert!(sv.reuses_force());
        assert_eq!(sv.forces(), 1);
        let fr = Sequence::of("forest-ruth").unwrap();
        assert_eq!(fr.flows().len(), 7);
        assert_eq!(fr.forces(), 3);
        let sum = |kind| -> f64 { fr.flows().iter().filter(|f| f.0 == kind).map(|f| f.1).sum() };
        assert!((sum(Drift) - 1.0).abs() < 1e-15 && (sum(Kick) - 1.0).abs() < 1e-15);
        for id in ["rk4", "euler", "midpoint", "no-such-method"] {
            assert_eq!(Sequence::of(id), None, "{id}");
        }
    }
}
