//! The drift–kick sequence a banded step applies, by method id: the one
//! description of such a step ([`integrator_core::sequence::Sequence`]),
//! with `Part::A` the drift `q += h·c·M⁻¹p` and `Part::B` the kick
//! `p += h·c·F(q)`, each applied with compensated summation as the
//! library's split steps apply them.

use integrator_core::Part;
use integrator_core::interp::SplittingInterpreter;
use integrator_core::sequence::Sequence;

/// The sequence of the explicit method `id`, or `None` where it is no
/// sequence of plain drifts and kicks (Runge–Kutta tables, implicit ones,
/// gradient kicks).
///
/// Library drift–kick sequences and compositions of Störmer–Verlet
/// (`leapfrog`, `forest-ruth`, …) come from the catalogue through
/// [`SplittingInterpreter`], which rounds the coefficients exactly as
/// `butcher!` does for the scheme's own step: the banded step then applies
/// the same flows with the same arithmetic as
/// [`SchemeStepper`](crate::step::SchemeStepper), and its trajectory is the
/// same to the bit (tested). The three explicit partitioned pairs are
/// written out: `symplectic-euler-a` (`â = 1`: p first) is a kick then a
/// drift, `symplectic-euler-b` a drift then a kick, `stormer-verlet`
/// (Lobatto IIIA–IIIB) kick ½, drift 1, kick ½. Their own steps form the
/// stage values without the carried rounding errors and update `p` once
/// from both forces, so they agree with these sequences to round-off, not
/// to the bit (tested).
pub fn sequence_of(id: &str) -> Option<Sequence> {
    let (drift, kick) = (Part::A, Part::B);
    Some(match id {
        "symplectic-euler-a" => Sequence::new([(kick, 1.0), (drift, 1.0)]),
        "symplectic-euler-b" => Sequence::new([(drift, 1.0), (kick, 1.0)]),
        "stormer-verlet" => Sequence::new([(kick, 0.5), (drift, 1.0), (kick, 0.5)]),
        _ => SplittingInterpreter::from_catalogue(id)
            .ok()?
            .sequence()
            .clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sequences_of_the_library() {
        let (drift, kick) = (Part::A, Part::B);
        let lf = sequence_of("leapfrog").unwrap();
        assert_eq!(lf.ops(), &[(drift, 0.5), (kick, 1.0), (drift, 0.5)]);
        let sv = sequence_of("stormer-verlet").unwrap();
        assert_eq!(sv.ops(), &[(kick, 0.5), (drift, 1.0), (kick, 0.5)]);
        let fr = sequence_of("forest-ruth").unwrap();
        assert_eq!(fr.ops().len(), 7);
        let sum = |kind| -> f64 { fr.ops().iter().filter(|f| f.0 == kind).map(|f| f.1).sum() };
        assert!((sum(drift) - 1.0).abs() < 1e-15 && (sum(kick) - 1.0).abs() < 1e-15);
        for id in ["rk4", "euler", "midpoint", "no-such-method"] {
            assert_eq!(sequence_of(id), None, "{id}");
        }
    }
}
