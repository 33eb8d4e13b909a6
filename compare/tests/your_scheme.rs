//! A scheme and a problem declared here, outside the library, go through
//! the library's API into the same sweep, CSV and report as the library's
//! own schemes; bad input comes back as error values that name the culprit.

use compare::{
    AsSeparable, CompareError, Defaults, Method, Problem, Setup, Stepper, SweepSettings,
    work_precision,
};
use integrator_core::problems::{Kepler, reference_solution};
use integrator_core::{Separable, SolveError, Step, butcher};

butcher! {
    /// Suzuki's fractal: five Störmer–Verlet steps, order 4 (not in the
    /// library).
    pub Suzuki4 {
        let p = 1/(4 - cbrt(4));
        claims: [symplectic, symmetric, order = 4],
        compose: [p, p, 1 - 4*p, p, p],
    }
}

/// A quartic oscillator, H = p²/2 + q⁴/4: no closed form, a computed
/// reference.
#[derive(Clone, Debug)]
struct Quartic;

impl Separable for Quartic {
    fn dof(&self) -> usize {
        1
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * p[0] * p[0]
    }
    fn potential(&self, q: &[f64]) -> f64 {
        0.25 * q[0].powi(4)
    }
    fn velocity(&self, p: &[f64], v: &mut [f64]) {
        v[0] = p[0];
    }
    fn force(&self, q: &[f64], f: &mut [f64]) {
        f[0] = -q[0].powi(3);
    }
}

impl Problem for Quartic {
    type Kind = AsSeparable;
    fn name(&self) -> String {
        "quartic".into()
    }
    fn energy(&self, z: &[f64]) -> f64 {
        integrator_core::energy(self, z)
    }
    fn start(&self) -> Vec<f64> {
        vec![1.0, 0.0]
    }
    fn reference(&self, z0: &[f64], t: f64) -> Result<Vec<f64>, String> {
        Ok(reference_solution(self, z0, t, 4000.0))
    }
    fn defaults(&self) -> Defaults {
        Defaults {
            t_end: 10.0,
            h_min: 2e-3,
            h_max: 0.2,
        }
    }
}

fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("compare-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn fitted(rows: &[compare::Row], method: &str) -> f64 {
    compare::output::fitted_order(rows, method).expect("enough runs to fit")
}

#[test]
fn a_scheme_declared_here_joins_a_sweep_beside_the_library() {
    let kepler = Kepler { e: 0.6 };
    let setup = Setup::new(kepler, 2.0 * std::f64::consts::PI).unwrap();
    let methods = vec![
        Method::scheme("suzuki4", Suzuki4),
        Method::by_id("forest-ruth", &kepler).unwrap(),
        Method::by_id("leapfrog", &kepler).unwrap(),
    ];
    let settings = SweepSettings {
        h_min: 2.0 * std::f64::consts::PI / 4000.0,
        h_max: 2.0 * std::f64::consts::PI / 200.0,
        points: 5,
        tolerances: vec![],
        repeats: 1,
        target: 1e-6,
    };
    let result = work_precision(&setup, &methods, &settings).unwrap();
    let suzuki: Vec<_> = result
        .rows
        .iter()
        .filter(|r| r.method == "suzuki4")
        .collect();
    assert_eq!(suzuki.len(), 5);
    assert!(
        suzuki
            .iter()
            .all(|r| r.ok() && r.symplectic && r.order == 4)
    );
    // Its fitted order matches its claim, as the library's order-4 scheme's does.
    let p = fitted(&result.rows, "suzuki4");
    assert!((p - 4.0).abs() < 0.3, "suzuki4 fitted order {p}");
    let q = fitted(&result.rows, "leapfrog");
    assert!((q - 2.0).abs() < 0.3, "leapfrog fitted order {q}");
    // Five force evaluations per step less the one first-same-as-last saves.
    let r = suzuki[0];
    assert!(
        r.evals >= 5 * r.steps && r.evals <= 5 * r.steps + 1,
        "{r:?}"
    );

    let dir = temp_dir("yours");
    let files = result.write(&dir).unwrap();
    assert!(files.iter().any(|f| f.ends_with("report.md")));
    let csv = std::fs::read_to_string(dir.join("runs.csv")).unwrap();
    let methods_in_csv: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap())
        .collect();
    for m in ["suzuki4", "forest-ruth", "leapfrog"] {
        assert!(methods_in_csv.contains(&m), "{m} not in runs.csv");
    }
    // The documented columns exactly: no interpreted table ran.
    assert!(csv.lines().next().unwrap().ends_with(",status"));
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(report.contains("| suzuki4 | 4 | yes |"), "{report}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_problem_declared_here_runs_library_schemes_by_id() {
    let setup = Setup::new(Quartic, 10.0).unwrap();
    let ids = setup.method_ids();
    assert!(ids.iter().any(|m| m == "kahan-li8") && ids.iter().any(|m| m == "gauss2"));
    let methods: Vec<Method<Quartic>> = ["rk4", "stormer-verlet", "gauss2"]
        .iter()
        .map(|id| setup.method(id).unwrap())
        .chain([Method::scheme("suzuki4", Suzuki4)])
        .collect();
    let settings = SweepSettings {
        points: 4,
        repeats: 1,
        tolerances: vec![],
        ..SweepSettings::new(Quartic.defaults(), 10.0)
    };
    let result = work_precision(&setup, &methods, &settings).unwrap();
    assert!(result.rows.iter().all(|r| r.ok() && r.problem == "quartic"));
    for (m, order) in [
        ("rk4", 4.0),
        ("stormer-verlet", 2.0),
        ("gauss2", 4.0),
        ("suzuki4", 4.0),
    ] {
        let p = fitted(&result.rows, m);
        assert!((p - order).abs() < 0.35, "{m}: fitted order {p}");
    }
}

#[derive(Clone, Debug)]
struct ShortReference;

impl Separable for ShortReference {
    fn dof(&self) -> usize {
        1
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * p[0] * p[0]
    }
    fn potential(&self, q: &[f64]) -> f64 {
        0.5 * q[0] * q[0]
    }
    fn velocity(&self, p: &[f64], v: &mut [f64]) {
        v[0] = p[0];
    }
    fn force(&self, q: &[f64], f: &mut [f64]) {
        f[0] = -q[0];
    }
}

impl Problem for ShortReference {
    type Kind = AsSeparable;
    fn name(&self) -> String {
        "short".into()
    }
    fn energy(&self, z: &[f64]) -> f64 {
        integrator_core::energy(self, z)
    }
    fn start(&self) -> Vec<f64> {
        vec![1.0, 0.0]
    }
    fn reference(&self, _z0: &[f64], _t: f64) -> Result<Vec<f64>, String> {
        Ok(vec![1.0, 0.0, 0.0])
    }
    fn defaults(&self) -> Defaults {
        Defaults {
            t_end: 1.0,
            h_min: 0.01,
            h_max: 0.1,
        }
    }
}

#[test]
fn bad_problems_and_settings_are_errors_that_name_them() {
    let e = Setup::new(ShortReference, 1.0).unwrap_err();
    assert!(matches!(e, CompareError::Problem { .. }));
    let msg = e.to_string();
    assert!(
        msg.contains("short") && msg.contains("reference") && msg.contains("3 components"),
        "{msg}"
    );
    let e = Setup::from_start(Quartic, vec![1.0], 1.0).unwrap_err();
    assert!(
        e.to_string().contains("start state has 1 components"),
        "{e}"
    );
    let e = Setup::from_start(Quartic, vec![f64::NAN, 0.0], 1.0).unwrap_err();
    assert!(e.to_string().contains("non-finite"), "{e}");
    for t in [0.0, -1.0, f64::INFINITY, f64::NAN] {
        let e = Setup::new(Quartic, t).unwrap_err();
        assert!(e.to_string().starts_with("t_end"), "{e}");
    }

    let setup = Setup::new(Quartic, 1.0).unwrap();
    let methods = vec![Method::scheme("suzuki4", Suzuki4)];
    let good = SweepSettings::new(Quartic.defaults(), 1.0);
    let cases: Vec<(SweepSettings, &str)> = vec![
        (
            SweepSettings {
                h_min: 0.0,
                ..good.clone()
            },
            "h_min",
        ),
        (
            SweepSettings {
                h_max: f64::NAN,
                ..good.clone()
            },
            "h_max",
        ),
        (
            SweepSettings {
                h_min: 0.5,
                h_max: 0.1,
                ..good.clone()
            },
            "h_min",
        ),
        (
            SweepSettings {
                h_max: 2.0,
                ..good.clone()
            },
            "h_max",
        ),
        (
            SweepSettings {
                h_min: 1e-12,
                ..good.clone()
            },
            "h_min",
        ),
        (
            SweepSettings {
                points: 0,
                ..good.clone()
            },
            "points",
        ),
        (
            SweepSettings {
                repeats: 0,
                ..good.clone()
            },
            "repeats",
        ),
        (
            SweepSettings {
                target: -1.0,
                ..good.clone()
            },
            "target",
        ),
        (
            SweepSettings {
                tolerances: vec![1e-6, 0.0],
                ..good.clone()
            },
            "tolerances",
        ),
    ];
    for (s, field) in cases {
        match work_precision(&setup, &methods, &s) {
            Err(CompareError::Setting { name, .. }) => assert_eq!(name, field, "{s:?}"),
            Err(e) => panic!("{s:?}: {e}"),
            Ok(_) => panic!("{s:?} accepted"),
        }
    }
    let none: Vec<Method<Quartic>> = vec![];
    assert!(matches!(
        work_precision(&setup, &none, &good),
        Err(CompareError::Setting {
            name: "methods",
            ..
        })
    ));
    let energy_only = Setup::energy_only(Quartic, 1.0).unwrap();
    let e = work_precision(&energy_only, &methods, &good).err().unwrap();
    assert!(e.to_string().contains("reference"), "{e}");
    let e = Method::by_id("no-such-scheme", &Quartic).err().unwrap();
    assert!(
        e.to_string().contains("unknown method 'no-such-scheme'"),
        "{e}"
    );
}

/// Explicit Euler that gives up at t ≥ 0.5: a scheme that fails at step k.
#[derive(Clone, Copy)]
struct GivesUp;

impl<S: integrator_core::OdeSystem + ?Sized> Step<S> for GivesUp {
    type Workspace = Vec<f64>;
    fn workspace(&self, sys: &S) -> Vec<f64> {
        vec![0.0; sys.dim()]
    }
    fn step(
        &self,
        sys: &S,
        t: f64,
        h: f64,
        z: &mut [f64],
        ws: &mut Vec<f64>,
    ) -> Result<(), SolveError> {
        if t >= 0.5 {
            return Err(SolveError::Singular);
        }
        sys.rhs(t, z, ws);
        for (zi, d) in z.iter_mut().zip(ws.iter()) {
            *zi += h * d;
        }
        Ok(())
    }
}

/// Explicit Euler with a step that blows up from t ≥ 0.3 on.
#[derive(Clone, Copy)]
struct BlowsUp;

impl<S: integrator_core::OdeSystem + ?Sized> Step<S> for BlowsUp {
    type Workspace = Vec<f64>;
    fn workspace(&self, _: &S) -> Vec<f64> {
        vec![]
    }
    fn step(
        &self,
        _: &S,
        t: f64,
        _h: f64,
        z: &mut [f64],
        _: &mut Vec<f64>,
    ) -> Result<(), SolveError> {
        if t >= 0.3 {
            z[0] = f64::INFINITY;
        }
        Ok(())
    }
}

#[test]
fn a_scheme_that_fails_at_step_k_is_a_row_that_says_so() {
    let setup = Setup::new(Quartic, 1.0).unwrap();
    let stepper = |s: Box<dyn Stepper<Quartic>>, id: &str| {
        Method::stepper(id, 1, false, compare::Family::ExplicitRk, s)
    };
    let methods = vec![
        stepper(Box::new(compare::StepStepper(GivesUp)), "gives-up"),
        stepper(Box::new(compare::StepStepper(BlowsUp)), "blows-up"),
    ];
    let settings = SweepSettings {
        h_min: 0.1,
        h_max: 0.1,
        points: 1,
        tolerances: vec![],
        repeats: 1,
        target: 1e-6,
    };
    let result = work_precision(&setup, &methods, &settings).unwrap();
    let status = |m: &str| {
        result
            .rows
            .iter()
            .find(|r| r.method == m)
            .unwrap()
            .status
            .clone()
    };
    // Steps are numbered from 1: the step from t = 0.5 is the sixth.
    assert_eq!(
        status("gives-up"),
        "solver failed at step 6: the stage matrix I − h·A⊗J is singular"
    );
    assert_eq!(status("blows-up"), "diverged at step 4");
    assert!(
        result
            .rows
            .iter()
            .all(|r| r.error.is_nan() && r.time_s.is_nan())
    );
}

/// Explicit Euler that panics from t ≥ 0.3 on: user code with a bug.
#[derive(Clone, Copy)]
struct Panics;

impl<S: integrator_core::OdeSystem + ?Sized> Step<S> for Panics {
    type Workspace = Vec<f64>;
    fn workspace(&self, sys: &S) -> Vec<f64> {
        vec![0.0; sys.dim()]
    }
    fn step(
        &self,
        sys: &S,
        t: f64,
        h: f64,
        z: &mut [f64],
        ws: &mut Vec<f64>,
    ) -> Result<(), SolveError> {
        if t >= 0.3 {
            let v: Vec<f64> = vec![];
            let _ = v[7]; // index out of bounds
        }
        sys.rhs(t, z, ws);
        for (zi, d) in z.iter_mut().zip(ws.iter()) {
            *zi += h * d;
        }
        Ok(())
    }
}

/// The quartic oscillator whose force panics once |q| < 0.9: a problem
/// with a bug, found only after a few steps.
#[derive(Clone, Debug)]
struct PanickyQuartic;

impl Separable for PanickyQuartic {
    fn dof(&self) -> usize {
        1
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * p[0] * p[0]
    }
    fn potential(&self, q: &[f64]) -> f64 {
        0.25 * q[0].powi(4)
    }
    fn velocity(&self, p: &[f64], v: &mut [f64]) {
        v[0] = p[0];
    }
    fn force(&self, q: &[f64], f: &mut [f64]) {
        assert!(
            q[0].abs() >= 0.9,
            "the force is not defined at q = {}",
            q[0]
        );
        f[0] = -q[0].powi(3);
    }
}

impl Problem for PanickyQuartic {
    type Kind = AsSeparable;
    fn name(&self) -> String {
        "panicky-quartic".into()
    }
    fn energy(&self, z: &[f64]) -> f64 {
        integrator_core::energy(self, z)
    }
    fn start(&self) -> Vec<f64> {
        vec![1.0, 0.0]
    }
    fn reference(&self, _z0: &[f64], _t: f64) -> Result<Vec<f64>, String> {
        Ok(vec![0.0, -0.5])
    }
    fn defaults(&self) -> Defaults {
        Quartic.defaults()
    }
}

#[test]
fn a_scheme_that_panics_is_a_failed_row_and_the_sweep_goes_on() {
    let setup = Setup::new(Quartic, 1.0).unwrap();
    let methods = vec![
        Method::stepper(
            "panics",
            1,
            false,
            compare::Family::ExplicitRk,
            Box::new(compare::StepStepper(Panics)),
        ),
        Method::scheme("suzuki4", Suzuki4),
    ];
    let settings = SweepSettings {
        h_min: 0.05,
        h_max: 0.1,
        points: 2,
        tolerances: vec![],
        repeats: 1,
        target: 1e-6,
    };
    let result = work_precision(&setup, &methods, &settings).unwrap();
    assert_eq!(result.rows.len(), 4, "{:?}", result.rows);
    let panics: Vec<_> = result
        .rows
        .iter()
        .filter(|r| r.method == "panics")
        .collect();
    assert_eq!(panics.len(), 2);
    // h = 0.1: the step from t = 0.3 is the fourth; h = 0.05: the seventh.
    let want = ["panicked at step 4: ", "panicked at step 7: "];
    for (r, want) in panics.iter().zip(want) {
        assert!(!r.ok());
        assert!(
            r.status.starts_with(want) && r.status.contains("index out of bounds"),
            "{}",
            r.status
        );
        assert!(r.error.is_nan() && r.time_s.is_nan());
    }
    let good: Vec<_> = result
        .rows
        .iter()
        .filter(|r| r.method == "suzuki4")
        .collect();
    assert_eq!(good.len(), 2);
    assert!(
        good.iter().all(|r| r.ok() && r.error.is_finite()),
        "{good:?}"
    );
    // The row survives the CSV round trip, the message with its commas.
    let dir = temp_dir("panics");
    result.write(&dir).unwrap();
    let back = compare::output::read_runs(&dir.join("runs.csv")).unwrap();
    assert_eq!(back[0].status, panics[0].status);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_problem_that_panics_is_a_failed_row_for_every_method() {
    let setup = Setup::new(PanickyQuartic, 1.0).unwrap();
    let methods = vec![
        Method::scheme("suzuki4", Suzuki4),
        Method::by_id("rk4", &PanickyQuartic).unwrap(),
    ];
    let settings = SweepSettings {
        h_min: 0.1,
        h_max: 0.1,
        points: 1,
        tolerances: vec![],
        repeats: 1,
        target: 1e-6,
    };
    let result = work_precision(&setup, &methods, &settings).unwrap();
    assert_eq!(result.rows.len(), 2);
    for r in &result.rows {
        assert!(
            r.status.starts_with("panicked at step ")
                && r.status.contains("the force is not defined at q = "),
            "{}: {}",
            r.method,
            r.status
        );
    }
    // A problem whose start panics is an error naming the panic, not a crash.
    #[derive(Clone, Debug)]
    struct NoStart;
    impl Separable for NoStart {
        fn dof(&self) -> usize {
            1
        }
        fn kinetic(&self, p: &[f64]) -> f64 {
            0.5 * p[0] * p[0]
        }
        fn potential(&self, q: &[f64]) -> f64 {
            0.5 * q[0] * q[0]
        }
        fn velocity(&self, p: &[f64], v: &mut [f64]) {
            v[0] = p[0];
        }
        fn force(&self, q: &[f64], f: &mut [f64]) {
            f[0] = -q[0];
        }
    }
    impl Problem for NoStart {
        type Kind = AsSeparable;
        fn name(&self) -> String {
            "no-start".into()
        }
        fn energy(&self, z: &[f64]) -> f64 {
            integrator_core::energy(self, z)
        }
        fn start(&self) -> Vec<f64> {
            unimplemented!("no start yet")
        }
        fn reference(&self, z0: &[f64], _t: f64) -> Result<Vec<f64>, String> {
            Ok(z0.to_vec())
        }
        fn defaults(&self) -> Defaults {
            Quartic.defaults()
        }
    }
    let e = Setup::new(NoStart, 1.0).unwrap_err().to_string();
    assert!(e.contains("panicked") && e.contains("no start yet"), "{e}");
}
