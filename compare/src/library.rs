//! The scheme library by id: `symlab list`'s ids mapped to the `butcher!`
//! types of `integrator_core::library`, as steppers of any problem that
//! they can step, and the exact propagators of the Gauss tables.

use integrator_core::Separable;
use integrator_core::library::*;

use crate::counting::{AsOde, AsSeparable};
use crate::method::{Fixed, Method, family_of, symplectic_for};
use crate::problem::{ByKind, Kind, Problem};
use crate::stepper::{FixedSizeStepper, StepStepper, Stepper};

/// Declares the library by id from integrator-core's one list
/// ([`integrator_core::for_each_scheme!`]): which schemes step any
/// `OdeSystem` (`explicit_rk`, `implicit_rk`: Runge–Kutta tables) and which
/// only separable Hamiltonians (`explicit_pairs`, and `splittings`: drift–kick
/// sequences and compositions, which also step Wisdom–Holman splits, see
/// [`wisdom_holman`](crate::wisdom_holman); `implicit_pairs`, which step
/// `Hamiltonian`s — all our Hamiltonian problems are separable). Emits the
/// id lists and the constructors, among them the time-transformed variants
/// of the explicit separable schemes (`logh:ID`);
/// `tests::library_lists_cover_the_registry` checks the lists against
/// `REGISTRY`. Explicit schemes are [`FixedSizeStepper`] steppers (fixed-size state
/// for small problems in timed runs: integrator-core's `tests/registry.rs`
/// proves that every scheme of the explicit groups has that path),
/// implicit ones [`StepStepper`].
macro_rules! library {
    (
        explicit_rk: [$($eid:literal => $ety:ident),* $(,)?],
        implicit_rk: [$($rid:literal => $rty:ident),* $(,)?],
        explicit_pairs: [$($xid:literal => $xty:ident),* $(,)?],
        splittings: [$($sid:literal => $sty:ident),* $(,)?],
        implicit_pairs: [$($iid:literal => $ity:ident),* $(,)?] $(,)?
    ) => {
        /// Ids of the Runge–Kutta tables (they step every `OdeSystem`).
        pub const RK_IDS: &[&str] = &[$($eid,)* $($rid),*];
        /// Ids of the schemes that step separable Hamiltonians only.
        pub const SEPARABLE_IDS: &[&str] = &[$($xid,)* $($sid,)* $($iid),*];
        /// Ids of the explicit schemes for separable Hamiltonians: those
        /// that also step the logarithmic Hamiltonian (`logh:ID`).
        pub const EXPLICIT_SEPARABLE_IDS: &[&str] = &[$($xid,)* $($sid),*];
        /// Ids of the splittings (drift–kick sequences and compositions):
        /// those that also step the Wisdom–Holman split of an N-body
        /// problem (`wh:ID`).
        pub const SPLITTING_IDS: &[&str] = &[$($sid),*];

        /// The time-transformed variant `logh:ID` of an explicit separable
        /// scheme on a separable problem, `None` for any other id.
        pub fn logh_stepper<P>(id: &str) -> Option<Box<dyn Stepper<P>>>
        where
            P: Problem<Kind = AsSeparable> + Separable,
        {
            Some(match id {
                $($xid => Box::new(crate::time_transformed::LogH($xty)),)*
                $($sid => Box::new(crate::time_transformed::LogH($sty)),)*
                _ => return None,
            })
        }

        /// Any library scheme on a separable problem, `None` for an id not
        /// in the library.
        pub fn separable_stepper<P>(id: &str) -> Option<Box<dyn Stepper<P>>>
        where
            P: Problem<Kind = AsSeparable> + Separable,
        {
            Some(match id {
                $($eid => Box::new(FixedSizeStepper($ety)),)*
                $($rid => Box::new(StepStepper($rty)),)*
                $($xid => Box::new(FixedSizeStepper($xty)),)*
                $($sid => Box::new(FixedSizeStepper($sty)),)*
                $($iid => Box::new(StepStepper($ity)),)*
                _ => return None,
            })
        }

        /// A Runge–Kutta table on any problem, `None` for any other id.
        pub fn rk_stepper<P: Problem>(id: &str) -> Option<Box<dyn Stepper<P>>> {
            Some(match id {
                $($eid => Box::new(FixedSizeStepper($ety)),)*
                $($rid => Box::new(StepStepper($rty)),)*
                _ => return None,
            })
        }
    };
}

integrator_core::for_each_scheme!(library);

/// The library scheme `id` as a stepper of `P`: `None` for an id that is
/// not in the library or whose scheme cannot step `P` (a splitting on a
/// system that is not separable).
pub fn stepper<P: Problem>(id: &str) -> Option<Box<dyn Stepper<P>>> {
    struct Library<'a>(&'a str);
    impl<P: Problem> ByKind<P> for Library<'_> {
        type Output = Option<Box<dyn Stepper<P>>>;
        fn separable(self) -> Self::Output
        where
            P: Problem<Kind = AsSeparable> + Separable,
        {
            separable_stepper::<P>(self.0)
        }
        fn ode(self) -> Self::Output
        where
            P: Problem<Kind = AsOde>,
        {
            rk_stepper::<P>(self.0)
        }
    }
    <P::Kind as Kind<P>>::by_kind(Library(id))
}

/// The library schemes that step `P`: every one on a separable problem,
/// the Runge–Kutta tables on any other.
pub fn ids<P: Problem>() -> Vec<&'static str> {
    if <P::Kind as Kind<P>>::SEPARABLE {
        RK_IDS.iter().chain(SEPARABLE_IDS).copied().collect()
    } else {
        RK_IDS.to_vec()
    }
}

/// The explicit separable scheme `id` on the logarithmic Hamiltonian of
/// `P` (`logh:ID`): `None` if `id` is not one or `P` is not separable.
pub fn logh<P: Problem>(id: &str) -> Option<Box<dyn Stepper<P>>> {
    struct LogH<'a>(&'a str);
    impl<P: Problem> ByKind<P> for LogH<'_> {
        type Output = Option<Box<dyn Stepper<P>>>;
        fn separable(self) -> Self::Output
        where
            P: Problem<Kind = AsSeparable> + Separable,
        {
            // The constant alone as the condition: rustc drops the branch
            // it rules out, with every scheme's copy it would instantiate,
            // before code generation (`Problem::NEGATIVE_POTENTIAL`).
            if P::NEGATIVE_POTENTIAL {
                logh_stepper::<P>(self.0)
            } else {
                None
            }
        }
        fn ode(self) -> Self::Output
        where
            P: Problem<Kind = AsOde>,
        {
            None
        }
    }
    <P::Kind as Kind<P>>::by_kind(LogH(id))
}

impl<P: Problem> Method<P> {
    /// A library scheme by id (`symlab list`), if it can step `P`.
    pub fn library(id: &str) -> Option<Self> {
        let stepper = stepper::<P>(id)?;
        let i = info(id)?;
        Some(Method::Fixed(Fixed {
            id: id.to_string(),
            order: i.order,
            symplectic: symplectic_for::<P>(i.symplectic, i.symplectic_separable),
            family: family_of(i),
            interpreted: false,
            stepper,
        }))
    }
}

/// The Gauss tables whose propagators are offered on the linear system, as
/// `(id, P, Q)` of their stability functions.
pub fn propagator_tables() -> Vec<(&'static str, Vec<f64>, Vec<f64>)> {
    vec![
        (
            "gauss1-propagator",
            GaussLegendre1::STABILITY_P.to_vec(),
            GaussLegendre1::STABILITY_Q.to_vec(),
        ),
        (
            "gauss2-propagator",
            GaussLegendre2::STABILITY_P.to_vec(),
            GaussLegendre2::STABILITY_Q.to_vec(),
        ),
        (
            "gauss3-propagator",
            GaussLegendre3::STABILITY_P.to_vec(),
            GaussLegendre3::STABILITY_Q.to_vec(),
        ),
    ]
}

/// Whether `id` is one of the [`propagator_tables`].
pub fn is_propagator(id: &str) -> bool {
    propagator_tables().iter().any(|(p, _, _)| *p == id)
}
