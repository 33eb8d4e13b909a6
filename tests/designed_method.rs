//! The designed method of the pendulum comparison, compiled by `butcher!`
//! from its emitted table file (`designs/found/`, as the
//! `designed_method` example compiles it): its claims proven at compile
//! time from the file, its steps those of the run-time interpreter on the
//! same file, and, in a sweep beside the library, fewer force evaluations
//! than the library's best at every error the sweep brackets (evaluations
//! are counted, not timed: the example measures the times).

use compare::versus::{Verdict, versus};
use compare::{Method, Problem, SweepSettings, work_precision};
use integrator_core::butcher;
use integrator_core::problems::Pendulum;

butcher! {
    pub Designed {
        file: "designs/found/rkn-aba-8-stages-order-6-3.toml",
    }
}

const DESIGN: &str = "rkn-aba-8-stages-order-6-3";
const FILE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/designs/found/rkn-aba-8-stages-order-6-3.toml"
);

#[test]
fn the_compiled_design_steps_as_its_table_file_and_needs_fewer_evaluations() {
    use integrator_core::Scheme;
    let info = <Designed as Scheme>::INFO;
    assert!(info.symplectic_separable, "{info:?}");
    let defaults = Pendulum.defaults();
    let setup = compare::builtin::pendulum(defaults.t_end, true).unwrap();
    let compiled = Method::scheme(DESIGN, Designed);
    let interpreted = Method::table_file(std::path::Path::new(FILE)).unwrap();
    let mut methods = vec![compiled, interpreted];
    for id in ["blanes-moan-prk10", "blanes-moan-srkn14a", "kahan-li8"] {
        methods.push(Method::by_id(id, &setup.sys).unwrap());
    }
    let settings = SweepSettings {
        h_min: 0.1,
        h_max: 0.8,
        points: 8,
        repeats: 1,
        ..SweepSettings::new(defaults, defaults.t_end)
    };
    let result = work_precision(&setup, &methods, &settings).unwrap();
    let rows =
        |m: &str| -> Vec<&compare::Row> { result.rows.iter().filter(|r| r.method == m).collect() };
    // The table file's row has the file's stem as its id: the same method.
    let (c, i) = (rows(DESIGN), rows(DESIGN));
    assert_eq!(c.len(), 16, "both rows, 8 step sizes each");
    let (c, i): (Vec<_>, Vec<_>) = (
        c.iter().filter(|r| !r.interpreted).collect(),
        i.iter().filter(|r| r.interpreted).collect(),
    );
    for (a, b) in c.iter().zip(&i) {
        assert_eq!((a.steps, a.evals), (b.steps, b.evals));
        assert!(
            (a.error - b.error).abs() <= 1e-9 * a.error.max(1e-12),
            "h = {}: {} vs {}",
            a.h,
            a.error,
            b.error
        );
    }
    // Generated rows only: the design against the library by evaluations.
    let generated: Vec<compare::Row> = result
        .rows
        .iter()
        .filter(|r| !r.interpreted)
        .cloned()
        .collect();
    let v = versus(&generated, &[DESIGN.to_string()], &[1e-6, 1e-8, 1e-10]);
    for t in &v.targets {
        match &t.evaluations {
            Verdict::DesignLess { ratio } => assert!(*ratio > 1.1, "{}", t.line()),
            _ => panic!("{}", t.line()),
        }
        let (d, l) = t.eval_pair.clone().unwrap();
        assert_eq!((d.as_str(), l.as_str()), (DESIGN, "blanes-moan-prk10"));
    }
}
