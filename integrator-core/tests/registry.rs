//! The library's one list (`integrator_core::for_each_scheme!`) against the
//! facts `butcher!` proved for each of its schemes, and against the
//! catalogue: a scheme in the wrong group, an id listed twice, a catalogue
//! table the library forgot, or a `REGISTRY` that disagrees with the list
//! fails here, not in a consumer (compare's steppers, cloth's methods) that
//! trusts the groups.

use integrator_core::library::*;
use integrator_core::problems::Kepler;
use integrator_core::{Info, Scheme, Step, StepFixed};

/// The list as `(group, [(id, facts)])`.
macro_rules! groups {
    ($($group:ident: [$($id:literal => $ty:ident),* $(,)?]),* $(,)?) => {
        [$((stringify!($group), &[$(($id, <$ty as Scheme>::INFO)),*] as &[(&str, Info)])),*]
    };
}

const GROUPS: [(&str, &[(&str, Info)]); 5] = integrator_core::for_each_scheme!(groups);

#[test]
fn the_groups_come_in_their_documented_order() {
    let names = GROUPS.map(|(g, _)| g);
    assert_eq!(
        names,
        [
            "explicit_rk",
            "implicit_rk",
            "explicit_pairs",
            "splittings",
            "implicit_pairs"
        ]
    );
}

#[test]
fn every_scheme_is_in_the_group_its_facts_say() {
    for (group, schemes) in GROUPS {
        assert!(!schemes.is_empty(), "{group} is empty");
        for (id, info) in schemes {
            let rk = info.form == "rk";
            let fits = match group {
                "explicit_rk" => rk && info.explicit && info.class == "explicit",
                "implicit_rk" => rk && !info.explicit,
                // Pairs explicit on separable systems; drift–kick sequences
                // and compositions (products of the flows of two parts).
                "explicit_pairs" => info.form == "prk" && info.explicit,
                "splittings" => {
                    (info.form == "drift-kick" || info.form == "composition") && info.explicit
                }
                "implicit_pairs" => info.form == "prk" && !info.explicit,
                other => panic!("unknown group {other}"),
            };
            assert!(fits, "{id} is in {group} but its facts are {info:?}");
        }
    }
}

#[test]
fn the_registry_is_the_list_in_order() {
    let listed: Vec<(&str, Info)> = GROUPS
        .iter()
        .flat_map(|(_, schemes)| schemes.iter().copied())
        .collect();
    assert_eq!(listed.as_slice(), REGISTRY);
    let mut ids: Vec<&str> = listed.iter().map(|(id, _)| *id).collect();
    ids.sort_unstable();
    let n = ids.len();
    ids.dedup();
    assert_eq!(ids.len(), n, "an id is listed twice");
}

#[test]
fn every_catalogue_table_is_listed_and_every_other_id_is_generated() {
    for entry in tableau::catalogue::entries() {
        // A processed method (a kernel with a corrector) is not one scheme:
        // its kernel is a scheme of the list (or its sequence, stepped at run
        // time) and `integrator_core::processed` applies the corrector.
        if entry.load().unwrap().corrector.is_some() {
            continue;
        }
        let times = REGISTRY.iter().filter(|(id, _)| *id == entry.id).count();
        assert_eq!(
            times, 1,
            "catalogue table {} is in the library's list {times} times (add one line to \
             `__scheme_list!` in integrator-core/src/library.rs)",
            entry.id
        );
    }
    for (id, info) in REGISTRY {
        if tableau::catalogue::find(id).is_none() {
            let generated = tableau::algebraic::family::Generator::parse(id);
            assert!(
                generated.is_ok(),
                "{id} ({}) is neither a catalogue table nor a generated one",
                info.name
            );
        }
    }
}

/// What each group promises its consumers, as trait bounds: the explicit
/// groups have the fixed-size path, the implicit ones step through `Step`.
#[test]
fn the_groups_step_what_they_promise() {
    fn fixed<M: StepFixed<Kepler, 4>>(_: M) {}
    fn stepped<M: Step<Kepler>>(_: M) {}
    fn split<M: Step<RotationKick>>(_: M) {}
    macro_rules! bounds {
        (
            explicit_rk: [$($e:literal => $ety:ident),*],
            implicit_rk: [$($i:literal => $ity:ident),*],
            explicit_pairs: [$($x:literal => $xty:ident),*],
            splittings: [$($s:literal => $sty:ident),*],
            implicit_pairs: [$($p:literal => $pty:ident),*],
        ) => {
            $(fixed($ety);)*
            $(stepped($ity);)*
            $(fixed($xty);)*
            $(fixed($sty);)*
            $(split($sty);)*
            $(stepped($pty);)*
        };
    }
    integrator_core::for_each_scheme!(bounds);
}

/// A split system that is not separable: only `splittings` step it.
struct RotationKick;

impl integrator_core::split::StateSpace for RotationKick {
    fn state_len(&self) -> usize {
        2
    }
}

impl integrator_core::Split for RotationKick {
    fn flow_a(
        &self,
        h: f64,
        z: &mut [f64],
        _: integrator_core::split::PartBuffers<'_>,
        _: bool,
    ) -> Result<(), integrator_core::split::FlowError> {
        let (s, c) = h.sin_cos();
        let (q, p) = (z[0], z[1]);
        z[0] = c * q + s * p;
        z[1] = c * p - s * q;
        Ok(())
    }
    fn flow_b(
        &self,
        h: f64,
        z: &mut [f64],
        _: integrator_core::split::PartBuffers<'_>,
        _: bool,
    ) -> Result<(), integrator_core::split::FlowError> {
        z[1] -= h * z[0].sin();
        Ok(())
    }
}

/// The callback may be named by a path, as consumers in other modules do.
mod by_path {
    macro_rules! ids {
        ($($group:ident: [$($id:literal => $ty:ident),*],)*) => {
            &[$($($id),*),*]
        };
    }
    pub(crate) use ids;
}

#[test]
fn the_callback_may_be_named_by_a_path() {
    let a: &[&str] = integrator_core::for_each_scheme!(by_path::ids);
    let b: &[&str] = integrator_core::for_each_scheme!(crate::registry::by_path::ids);
    let registry: Vec<&str> = REGISTRY.iter().map(|(id, _)| *id).collect();
    assert_eq!(a, registry.as_slice());
    assert_eq!(a, b);
}
