//! `symlab.integrate`, the ensemble call and the comparisons: the
//! comparison library's own code (`compare`), called as `symlab compare`
//! calls it, so that rows agree with the command line's. The GIL is
//! released while Rust steps; a Python problem's callables take it back for
//! each call.

use std::any::Any;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use compare::builtin::Builtin;
use compare::interpreted::VerifiedTable;
use compare::plan::{self, OnSetup};
use compare::registry::MethodSpec;
use compare::sweep_plan::{FromFile, Names, SweepRequest};
use compare::{Method, Problem as CmpProblem, Row, Setup};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString};

use crate::errors::{IntegrationError, ProblemError};
use crate::problem::{Problem, PyOde, PySeparable, PySystem};
use crate::table::Table;

/// A method as given: a scheme id or a verified table.
#[derive(Clone)]
pub enum MethodArg {
    Id(String),
    Table(Box<VerifiedTable>),
}

impl MethodArg {
    fn from_py(py: Python<'_>, m: &Bound<'_, PyAny>, what: &str) -> PyResult<Self> {
        if let Ok(s) = m.cast::<PyString>() {
            return Ok(MethodArg::Id(s.to_cow()?.into_owned()));
        }
        if let Ok(t) = m.cast::<Table>() {
            return Ok(MethodArg::Table(Box::new(t.get().verified(py)?)));
        }
        Err(PyTypeError::new_err(format!(
            "{what}: expected a scheme id (str, see symlab.list_tables()) or a symlab.Table, got {}",
            m.get_type().name()?
        )))
    }

    /// The method as the registry takes it.
    fn spec<P: CmpProblem>(&self) -> MethodSpec<P> {
        match self {
            MethodArg::Id(id) => MethodSpec::Id(id.clone()),
            MethodArg::Table(t) => MethodSpec::Table(t.clone()),
        }
    }

    fn method<P: CmpProblem>(&self, setup: &Setup<P>) -> Result<Method<P>, Fail> {
        self.spec()
            .resolve(setup)
            .map_err(|e| Fail::Problem(e.to_string()))
    }
}

/// What can go wrong in a run, turned into a Python exception once the GIL
/// is held again.
pub enum Fail {
    /// The problem, the method or a setting cannot run (`ProblemError`).
    Problem(String),
    /// A bad argument (`ValueError`), its message naming it.
    Value(String),
    /// The run diverged or its solver failed (`IntegrationError`).
    Run(String),
    /// A Python callable raised (its exception).
    Py(PyErr),
}

impl From<Fail> for PyErr {
    fn from(f: Fail) -> PyErr {
        match f {
            Fail::Problem(m) => ProblemError::new_err(m),
            Fail::Value(m) => PyValueError::new_err(m),
            Fail::Run(m) => IntegrationError::new_err(m),
            Fail::Py(e) => e,
        }
    }
}

/// A problem as given: a built-in's name or a `symlab.Problem`.
pub enum ProblemArg {
    Builtin(Builtin),
    Python(Arc<crate::problem::Spec>),
}

impl ProblemArg {
    fn from_py(p: &Bound<'_, PyAny>) -> PyResult<Self> {
        if let Ok(s) = p.cast::<PyString>() {
            let name = s.to_cow()?;
            let name: &str = &name;
            return Builtin::from_name(name)
                .map(ProblemArg::Builtin)
                .map_err(|_| {
                    ProblemError::new_err(format!(
                        "problem: unknown problem '{name}'; the built-in problems are {}",
                        Builtin::ALL.map(Builtin::name).join(", ")
                    ))
                });
        }
        if let Ok(pr) = p.cast::<Problem>() {
            return Ok(ProblemArg::Python(pr.get().spec.clone()));
        }
        Err(PyTypeError::new_err(format!(
            "problem: expected a built-in problem's name (str) or a symlab.Problem, got {}",
            p.get_type().name()?
        )))
    }
}

/// The built-in problems' names.
#[pyfunction]
pub fn problems() -> Vec<&'static str> {
    Builtin::ALL.map(Builtin::name).to_vec()
}

/// A state given from Python: float64, one dimension, finite.
fn state(y: Option<PyReadonlyArray1<'_, f64>>, what: &str) -> PyResult<Option<Vec<f64>>> {
    let Some(y) = y else { return Ok(None) };
    let v = y.as_array().to_vec();
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "{what}[{i}] is {}, not a finite number",
            v[i]
        )));
    }
    Ok(Some(v))
}

fn check_step(h: f64, n: usize) -> PyResult<()> {
    if !(h.is_finite() && h > 0.0) {
        return Err(PyValueError::new_err(format!(
            "h must be a finite number > 0, got {h}"
        )));
    }
    if n == 0 {
        return Err(PyValueError::new_err("n must be at least 1"));
    }
    Ok(())
}

/// A trajectory: the times and states recorded.
struct Traj {
    t: Vec<f64>,
    y: Vec<f64>,
    dim: usize,
}

/// `n` steps of the fixed-step `method` from `z`, recording every
/// `every`-th state (and the last).
fn drive<P: CmpProblem>(
    setup: &Setup<P>,
    method: &Method<P>,
    z0: Vec<f64>,
    t0: f64,
    h: f64,
    n: usize,
    every: usize,
) -> Result<Traj, Fail> {
    let Method::Fixed(f) = method else {
        return Err(Fail::Problem(format!(
            "method '{}' is adaptive (it chooses its own steps); symlab.integrate takes fixed-step schemes — compare it with symlab.compare",
            method.id()
        )));
    };
    let dim = z0.len();
    if dim != setup.z0.len() {
        return Err(Fail::Value(format!(
            "y0: expected {} components, got {dim}",
            setup.z0.len()
        )));
    }
    // Only the end asked for: the bare run, the very loop the comparisons
    // time (no counting wrapper, no observer), so that a call from Python
    // costs what the same run costs in Rust plus a fixed overhead. A run
    // that fails is stepped again, observed, for its status.
    if every >= n {
        let mut z = z0.clone();
        if let Ok(true) = compare::stepper::bare_caught(&*f.stepper, &setup.sys, &mut z, h, n) {
            let mut y = z0.clone();
            y.extend_from_slice(&z);
            return Ok(Traj {
                t: vec![t0, t0 + n as f64 * h],
                y,
                dim,
            });
        }
    }
    let mut z = z0;
    let mut t = Vec::with_capacity(n / every + 2);
    let mut y = Vec::with_capacity((n / every + 2) * dim);
    let outcome = compare::observed_caught(
        &*f.stepper,
        &setup.sys,
        &mut z,
        h,
        n,
        true,
        &mut |k, _, z| {
            if k % every == 0 || k == n {
                t.push(t0 + k as f64 * h);
                y.extend_from_slice(z);
            }
            true
        },
    );
    if !outcome.status.is_ok() {
        return Err(Fail::Run(format!(
            "{} on {}: {}",
            f.id,
            setup.name,
            outcome.status.label()
        )));
    }
    Ok(Traj { t, y, dim })
}

struct IntegrateJob {
    method: MethodArg,
    y0: Option<Vec<f64>>,
    t0: f64,
    h: f64,
    n: usize,
    every: usize,
}

impl OnSetup for IntegrateJob {
    type Output = Result<Traj, Fail>;
    fn run<P: CmpProblem>(self, setup: Setup<P>) -> Self::Output {
        let m = self.method.method(&setup)?;
        let z0 = self.y0.unwrap_or_else(|| setup.z0.clone());
        drive(&setup, &m, z0, self.t0, self.h, self.n, self.every)
    }
}

/// `(t, y)` as NumPy arrays.
type TimesStates<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray2<f64>>);

fn traj_to_py(py: Python<'_>, tr: Traj) -> PyResult<TimesStates<'_>> {
    let rows = tr.t.len();
    let t = PyArray1::from_vec(py, tr.t);
    let y = PyArray1::from_vec(py, tr.y).reshape([rows, tr.dim])?;
    Ok((t, y))
}

/// Step ``problem`` with ``scheme`` from ``y0`` at ``t0``: ``n`` steps of
/// size ``h``. Returns ``(t, y)``: the times and the states (one row each)
/// at every ``every``-th step (default: the start and the end only).
///
/// ``scheme``: a library id (``symlab.list_tables()``) or a ``symlab.Table``
/// (stepped by the run-time interpreter after its claims are verified).
/// ``problem``: a built-in's name (``symlab.problems()``) or a
/// ``symlab.Problem``. ``y0=None``: the problem's default start. The GIL
/// is released while Rust steps. A run that diverges or whose stage solver
/// fails raises ``IntegrationError``; a callable that raises or returns the
/// wrong shape raises ``ProblemError`` naming it (the original exception
/// is its ``__cause__``).
///
/// >>> import symlab
/// >>> t, y = symlab.integrate("gauss2", "kepler", None, 0.0, 0.01, 628)
/// >>> y.shape
/// (2, 4)
#[pyfunction]
#[pyo3(signature = (scheme, problem, y0, t0, h, n, *, every = None))]
#[allow(clippy::too_many_arguments)]
pub fn integrate<'py>(
    py: Python<'py>,
    scheme: &Bound<'py, PyAny>,
    problem: &Bound<'py, PyAny>,
    y0: Option<PyReadonlyArray1<'py, f64>>,
    t0: f64,
    h: f64,
    n: usize,
    every: Option<usize>,
) -> PyResult<TimesStates<'py>> {
    check_step(h, n)?;
    if !t0.is_finite() {
        return Err(PyValueError::new_err(format!(
            "t0 must be finite, got {t0}"
        )));
    }
    let every = every.unwrap_or(n);
    if every == 0 {
        return Err(PyValueError::new_err("every must be at least 1"));
    }
    let y0 = state(y0, "y0")?;
    let method = MethodArg::from_py(py, scheme, "scheme")?;
    let problem = ProblemArg::from_py(problem)?;
    let job = IntegrateJob {
        method,
        y0,
        t0,
        h,
        n,
        every,
    };
    let tr = match problem {
        ProblemArg::Builtin(b) => py
            .detach(|| plan::with_setup(b, 1.0, false, job))
            .map_err(|e| Fail::Problem(e.to_string()))??,
        ProblemArg::Python(spec) => {
            let sys = PySystem::new(spec.clone(), 1, t0);
            let r = py.detach(|| run_python(&sys, job));
            if let Some(e) = sys.take_error() {
                return Err(e);
            }
            r?
        }
    };
    traj_to_py(py, tr)
}

/// A job on a Python problem (separable or not).
fn run_python(sys: &PySystem, job: IntegrateJob) -> Result<Traj, Fail> {
    if sys.spec.is_separable() {
        let setup = python_setup(PySeparable(sys.clone()), sys)?;
        job.run(setup)
    } else {
        let setup = python_setup(PyOde(sys.clone()), sys)?;
        job.run(setup)
    }
}

/// A Python problem's setup for stepping: no reference and no energy
/// needed (an energy that is missing or not finite is NaN).
fn python_setup<P: CmpProblem>(p: P, sys: &PySystem) -> Result<Setup<P>, Fail> {
    let z0 = sys
        .spec
        .y0
        .clone()
        .map(|y| y.repeat(sys.batch))
        .unwrap_or_else(|| vec![0.0; sys.spec.dim() * sys.batch]);
    let e0 = p.energy(&z0);
    if let Some(e) = sys.take_error() {
        return Err(Fail::Py(e));
    }
    Ok(Setup {
        name: sys.spec.name.clone(),
        description: sys.spec.name.clone(),
        sys: p,
        z0,
        t_end: 1.0,
        reference: vec![],
        e0,
    })
}

/// Step many initial conditions (the rows of ``y0``, shape ``(m, dim)``)
/// with one scheme and ``n`` steps of size ``h``; returns the final states,
/// shape ``(m, dim)``. A built-in problem steps each row in turn in one
/// Rust loop (the GIL released); a ``symlab.Problem`` steps all rows as one
/// stacked system, each callable called once per stage with arrays of shape
/// ``(m, dof)`` — the NumPy-vectorised form.
#[pyfunction]
#[pyo3(signature = (scheme, problem, y0, h, n))]
pub fn integrate_ensemble<'py>(
    py: Python<'py>,
    scheme: &Bound<'py, PyAny>,
    problem: &Bound<'py, PyAny>,
    y0: PyReadonlyArray2<'py, f64>,
    h: f64,
    n: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    check_step(h, n)?;
    let y = y0.as_array();
    let (m, dim) = (y.nrows(), y.ncols());
    if m == 0 {
        return Err(PyValueError::new_err(
            "y0: no initial conditions (shape (0, dim))",
        ));
    }
    for ((i, j), x) in y.indexed_iter() {
        if !x.is_finite() {
            return Err(PyValueError::new_err(format!(
                "y0[{i}, {j}] is {x}, not a finite number"
            )));
        }
    }
    let rows: Vec<Vec<f64>> = y.outer_iter().map(|r| r.to_vec()).collect();
    let method = MethodArg::from_py(py, scheme, "scheme")?;
    let out: Vec<f64> = match ProblemArg::from_py(problem)? {
        ProblemArg::Builtin(b) => {
            struct Ensemble {
                method: MethodArg,
                rows: Vec<Vec<f64>>,
                h: f64,
                n: usize,
            }
            impl OnSetup for Ensemble {
                type Output = Result<Vec<f64>, Fail>;
                fn run<P: CmpProblem>(self, setup: Setup<P>) -> Self::Output {
                    let m = self.method.method(&setup)?;
                    let mut out = Vec::new();
                    for (i, z) in self.rows.into_iter().enumerate() {
                        let tr = drive(&setup, &m, z, 0.0, self.h, self.n, self.n).map_err(
                            |e| match e {
                                Fail::Value(msg) => {
                                    Fail::Value(msg.replace("y0:", &format!("y0[{i}]:")))
                                }
                                Fail::Run(msg) => {
                                    Fail::Run(format!("initial condition {i}: {msg}"))
                                }
                                other => other,
                            },
                        )?;
                        out.extend_from_slice(&tr.y[tr.y.len() - tr.dim..]);
                    }
                    Ok(out)
                }
            }
            let job = Ensemble { method, rows, h, n };
            py.detach(|| plan::with_setup(b, 1.0, false, job))
                .map_err(|e| Fail::Problem(e.to_string()))??
        }
        ProblemArg::Python(spec) => {
            if dim != spec.dim() {
                return Err(PyValueError::new_err(format!(
                    "y0: expected shape (m, {}), got (m, {dim})",
                    spec.dim()
                )));
            }
            let separable = spec.is_separable();
            let k = spec.n;
            // Stack: [q₁…q_m, p₁…p_m] for a separable problem, else [y₁…y_m].
            let mut z = Vec::with_capacity(m * dim);
            if separable {
                for r in &rows {
                    z.extend_from_slice(&r[..k]);
                }
                for r in &rows {
                    z.extend_from_slice(&r[k..]);
                }
            } else {
                for r in &rows {
                    z.extend_from_slice(r);
                }
            }
            let sys = PySystem::new(spec.clone(), m, 0.0);
            let job = IntegrateJob {
                method,
                y0: Some(z),
                t0: 0.0,
                h,
                n,
                every: n,
            };
            let r = py.detach(|| run_python(&sys, job));
            if let Some(e) = sys.take_error() {
                return Err(e);
            }
            let tr = r?;
            let last = &tr.y[tr.y.len() - tr.dim..];
            if separable {
                let (q, p) = last.split_at(m * k);
                let mut out = Vec::with_capacity(m * dim);
                for i in 0..m {
                    out.extend_from_slice(&q[i * k..(i + 1) * k]);
                    out.extend_from_slice(&p[i * k..(i + 1) * k]);
                }
                out
            } else {
                last.to_vec()
            }
        }
    };
    PyArray1::from_vec(py, out).reshape([m, dim])
}

// ---------------------------------------------------------------------------
// Comparisons.

/// The sweep settings from a dict, named as Python names them (`t_end`,
/// `h_min`, …) in messages.
fn request(settings: Option<&Bound<'_, PyDict>>) -> PyResult<SweepRequest> {
    let mut req = SweepRequest {
        names: Names {
            t_end: "t_end".into(),
            h_min: "h_min".into(),
            h_max: "h_max".into(),
            points: "points".into(),
            repeats: "repeats".into(),
            target: "target".into(),
        },
        from_file: FromFile::default(),
        ..Default::default()
    };
    let Some(s) = settings else { return Ok(req) };
    for (k, v) in s.iter() {
        let key: String = k.extract()?;
        let f = |v: &Bound<'_, PyAny>| -> PyResult<f64> {
            v.extract::<f64>()
                .map_err(|_| PyTypeError::new_err(format!("settings[{key:?}]: expected a number")))
        };
        let u = |v: &Bound<'_, PyAny>| -> PyResult<usize> {
            v.extract::<usize>().map_err(|_| {
                PyTypeError::new_err(format!(
                    "settings[{key:?}]: expected a non-negative integer"
                ))
            })
        };
        match key.as_str() {
            "t_end" => req.t_end = Some(f(&v)?),
            "h_min" => req.h_min = Some(f(&v)?),
            "h_max" => req.h_max = Some(f(&v)?),
            "points" => req.points = Some(u(&v)?),
            "repeats" => req.repeats = Some(u(&v)?),
            "target" => req.target = Some(f(&v)?),
            "quick" => req.quick = v.extract()?,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "settings: unknown key {key:?}; the keys are t_end, h_min, h_max, points, repeats, target, quick"
                )));
            }
        }
    }
    if req.repeats == Some(0) {
        return Err(PyValueError::new_err("repeats must be at least 1"));
    }
    Ok(req)
}

fn methods_arg(
    py: Python<'_>,
    methods: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<Vec<MethodArg>>> {
    let Some(list) = methods else { return Ok(None) };
    if list.is_instance_of::<PyString>() {
        return Err(PyTypeError::new_err(
            "methods: expected a list of ids or symlab.Table objects, got a str (write [\"gauss2\"])",
        ));
    }
    let mut out = Vec::new();
    for (i, m) in list.try_iter()?.enumerate() {
        out.push(MethodArg::from_py(py, &m?, &format!("methods[{i}]"))?);
    }
    Ok(Some(out))
}

/// The methods of a sweep, as `symlab compare` resolves them
/// ([`plan::sweep_methods`]): those given, else its defaults (with tables:
/// the table references).
fn resolve<P: CmpProblem>(
    setup: &Setup<P>,
    builtin: Option<Builtin>,
    given: &Option<Vec<MethodArg>>,
    quick: bool,
) -> Result<Vec<Method<P>>, Fail> {
    let named = given
        .as_ref()
        .map(|g| g.iter().map(MethodArg::spec).collect());
    plan::sweep_methods(setup, builtin, named, vec![], quick).map_err(|e| match e {
        compare::CompareError::DuplicateMethod { id, .. } => Fail::Problem(format!(
            "methods: the id '{id}' appears twice (a table's id is its file's stem or Table(id=...))"
        )),
        e => Fail::Problem(e.to_string()),
    })
}

pub fn row_to_py<'py>(py: Python<'py>, r: &Row) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("problem", &r.problem)?;
    d.set_item("method", &r.method)?;
    d.set_item("order", r.order)?;
    d.set_item("symplectic", r.symplectic)?;
    d.set_item("h", r.h)?;
    d.set_item("tol", r.tol)?;
    d.set_item("steps", r.steps)?;
    d.set_item("error", r.error)?;
    d.set_item("energy_error", r.energy_error)?;
    d.set_item("time_s", r.time_s)?;
    d.set_item("evals", r.evals)?;
    d.set_item("newton_iterations", r.newton_iterations)?;
    d.set_item("fixed_point_iterations", r.fixed_point_iterations)?;
    d.set_item("factorizations", r.factorizations)?;
    d.set_item("status", &r.status)?;
    d.set_item("interpreted", r.interpreted)?;
    Ok(d)
}

/// A sweep's problem: a built-in's setup, or a Python problem's.
struct Compare {
    builtin: Option<Builtin>,
    methods: Option<Vec<MethodArg>>,
    quick: bool,
    settings: compare::SweepSettings,
    out: Option<std::path::PathBuf>,
}

struct CompareOut {
    rows: Vec<Row>,
    summary: String,
    files: Vec<String>,
}

impl OnSetup for Compare {
    type Output = Result<CompareOut, Fail>;
    fn run<P: CmpProblem>(self, setup: Setup<P>) -> Self::Output {
        let methods = resolve(&setup, self.builtin, &self.methods, self.quick)?;
        let wp = compare::work_precision(&setup, &methods, &self.settings)
            .map_err(|e| Fail::Problem(e.to_string()))?;
        let mut files = Vec::new();
        if let Some(dir) = &self.out {
            std::fs::create_dir_all(dir)
                .map_err(|e| Fail::Value(format!("out: cannot create {}: {e}", dir.display())))?;
            files = wp
                .write(dir)
                .map_err(|e| Fail::Problem(e.to_string()))?
                .into_iter()
                .map(|p| p.display().to_string())
                .collect();
        }
        Ok(CompareOut {
            summary: wp.summary(),
            rows: wp.rows,
            files,
        })
    }
}

/// The local sweep (what `symlab.compare` calls without a client): rows
/// as dicts, the summary `symlab compare` prints, and the files written
/// when `out` is given.
#[pyfunction]
#[pyo3(signature = (problem, methods = None, settings = None, out = None))]
pub fn compare_local<'py>(
    py: Python<'py>,
    problem: &Bound<'py, PyAny>,
    methods: Option<&Bound<'py, PyAny>>,
    settings: Option<&Bound<'py, PyDict>>,
    out: Option<std::path::PathBuf>,
) -> PyResult<(Bound<'py, PyList>, String, Vec<String>)> {
    let req = request(settings)?;
    let methods = methods_arg(py, methods)?;
    let problem = ProblemArg::from_py(problem)?;
    let has_tables = methods
        .as_ref()
        .is_some_and(|m| m.iter().any(|x| matches!(x, MethodArg::Table(_))));
    let result = match problem {
        ProblemArg::Builtin(b) => {
            let plan = compare::sweep_plan::sweep_plan(&req, b.defaults())
                .map_err(|e| PyValueError::new_err(e.to_string()))?;
            let job = Compare {
                builtin: Some(b),
                methods,
                quick: req.quick || has_tables,
                settings: plan.settings,
                out,
            };
            py.detach(|| plan::with_setup(b, plan.t_end, true, job))
                .map_err(|e| Fail::Problem(e.to_string()))??
        }
        ProblemArg::Python(spec) => {
            let Some(defaults) = spec.defaults else {
                return Err(ProblemError::new_err(format!(
                    "problem {:?}: a comparison needs the problem's t_end, h_min and h_max (symlab.Problem(..., t_end=, h_min=, h_max=)) and its reference",
                    spec.name
                )));
            };
            let plan = compare::sweep_plan::sweep_plan(&req, defaults)
                .map_err(|e| PyValueError::new_err(e.to_string()))?;
            let sys = PySystem::new(spec.clone(), 1, 0.0);
            let job = Compare {
                builtin: None,
                methods,
                quick: req.quick || has_tables,
                settings: plan.settings,
                out,
            };
            let r = py.detach(|| -> Result<CompareOut, Fail> {
                if spec.is_separable() {
                    let setup = Setup::new(PySeparable(sys.clone()), plan.t_end)
                        .map_err(|e| Fail::Problem(e.to_string()))?;
                    job.run(setup)
                } else {
                    let setup = Setup::new(PyOde(sys.clone()), plan.t_end)
                        .map_err(|e| Fail::Problem(e.to_string()))?;
                    job.run(setup)
                }
            });
            if let Some(e) = sys.take_error() {
                return Err(e);
            }
            r?
        }
    };
    let rows = PyList::empty(py);
    for r in &result.rows {
        rows.append(row_to_py(py, r)?)?;
    }
    Ok((rows, result.summary, result.files))
}

// ---------------------------------------------------------------------------
// The distributed path: a plan of independent runs, and one run.

/// A sweep of a built-in problem as a list of independent runs, each a
/// dict ``{method, kind: "steps"|"tol", value, max_steps}``, in the order
/// of the local sweep's rows; with the sweep's ``t_end`` and ``repeats``.
#[pyfunction]
#[pyo3(signature = (problem, methods = None, settings = None))]
pub fn sweep_plan<'py>(
    py: Python<'py>,
    problem: &str,
    methods: Option<&Bound<'py, PyAny>>,
    settings: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyList>, f64, usize)> {
    let b = Builtin::from_name(problem).map_err(|e| ProblemError::new_err(e.to_string()))?;
    let req = request(settings)?;
    let given = methods_arg(py, methods)?;
    if let Some(g) = &given
        && g.iter().any(|m| matches!(m, MethodArg::Table(_)))
    {
        return Err(PyTypeError::new_err(
            "methods: the distributed sweep takes scheme ids; run tables with symlab.compare without client=",
        ));
    }
    let plan = compare::sweep_plan::sweep_plan(&req, b.defaults())
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    plan.settings
        .validate(plan.t_end)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    struct Ids {
        given: Option<Vec<MethodArg>>,
        quick: bool,
    }
    impl OnSetup for Ids {
        type Output = Result<Vec<(String, bool)>, Fail>;
        fn run<P: CmpProblem>(self, setup: Setup<P>) -> Self::Output {
            let ms = resolve(
                &setup,
                Builtin::from_name(&setup.name).ok(),
                &self.given,
                self.quick,
            )?;
            ms.iter()
                .map(|m| match m {
                    Method::Fixed(_) => Ok((m.id().to_string(), true)),
                    Method::Dop853 => Ok((m.id().to_string(), false)),
                    Method::Rebound(_) => Err(Fail::Problem(format!(
                        "methods: {} runs REBOUND in a Python process of its own; the distributed sweep runs this library's methods and dop853",
                        m.id()
                    ))),
                })
                .collect()
        }
    }
    let ids = py
        .detach(|| {
            plan::with_setup(
                b,
                plan.t_end,
                false,
                Ids {
                    given,
                    quick: req.quick,
                },
            )
        })
        .map_err(|e| Fail::Problem(e.to_string()))??;
    let steps = plan.settings.step_counts(plan.t_end);
    let fixed = ids.iter().filter(|m| m.1).count();
    let per_method: f64 = steps.iter().map(|&n| n as f64).sum();
    let runs = (2 + plan.settings.repeats) as f64;
    let total = fixed as f64 * per_method * runs;
    if total > compare::MAX_SWEEP_STEPS {
        return Err(PyValueError::new_err(format!(
            "h_min: the sweep asks for {total:.1e} steps in all; at most {:.0e} — raise h_min, or lower points, repeats or the number of methods",
            compare::MAX_SWEEP_STEPS
        )));
    }
    let max_steps = compare::sweep::peer_step_limit(&steps);
    let out = PyList::empty(py);
    for (id, fixed) in ids {
        let values: Vec<f64> = if fixed {
            steps.iter().map(|&n| n as f64).collect()
        } else {
            plan.settings.tolerances.clone()
        };
        for v in values {
            let d = PyDict::new(py);
            d.set_item("method", &id)?;
            d.set_item("kind", if fixed { "steps" } else { "tol" })?;
            d.set_item("value", v)?;
            d.set_item("max_steps", max_steps)?;
            out.append(d)?;
        }
    }
    Ok((out, plan.t_end, plan.settings.repeats))
}

/// The setups made in this process, by problem and end time: a worker
/// runs many points of one sweep, and a reference (outer-solar: a long
/// accurate integration) is computed once.
type SetupCache = Mutex<HashMap<(String, u64), Arc<dyn Any + Send + Sync>>>;

fn setups() -> &'static SetupCache {
    static CACHE: OnceLock<SetupCache> = OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(HashMap::new()))
}

struct Point {
    method: String,
    value: f64,
    max_steps: u32,
    repeats: usize,
    key: (String, u64),
}

impl OnSetup for Point {
    type Output = Result<Row, Fail>;
    fn run<P: CmpProblem>(self, setup: Setup<P>) -> Self::Output {
        let setup: Arc<Setup<P>> = {
            let mut cache = setups().lock().unwrap_or_else(|e| e.into_inner());
            match cache
                .get(&self.key)
                .and_then(|s| s.clone().downcast::<Setup<P>>().ok())
            {
                Some(s) => s,
                None => {
                    let s = Arc::new(setup);
                    cache.insert(self.key.clone(), s.clone());
                    s
                }
            }
        };
        let m = setup
            .method(&self.method)
            .map_err(|e| Fail::Problem(e.to_string()))?;
        Ok(match &m {
            Method::Fixed(f) => {
                compare::sweep::fixed_run(&setup, f, self.value as u64, self.repeats)
            }
            Method::Dop853 => {
                compare::sweep::peer_run(&setup, self.value, self.repeats, self.max_steps)
            }
            Method::Rebound(_) => {
                return Err(Fail::Problem(format!(
                    "{}: REBOUND's methods do not run in the distributed sweep",
                    self.method
                )));
            }
        })
    }
}

/// One point of a sweep plan (see ``sweep_plan``): the row of runs.csv,
/// exactly as the local sweep makes it (an observed run, a warm-up and
/// ``repeats`` timed runs, one after another). What each Dask task runs.
#[pyfunction]
#[pyo3(signature = (problem, t_end, repeats, method, kind, value, max_steps))]
#[allow(clippy::too_many_arguments)]
pub fn run_point<'py>(
    py: Python<'py>,
    problem: &str,
    t_end: f64,
    repeats: usize,
    method: String,
    kind: &str,
    value: f64,
    max_steps: u32,
) -> PyResult<Bound<'py, PyDict>> {
    let b = Builtin::from_name(problem).map_err(|e| ProblemError::new_err(e.to_string()))?;
    match kind {
        "steps" | "tol" => {}
        other => {
            return Err(PyValueError::new_err(format!(
                "kind must be \"steps\" or \"tol\", got {other:?}"
            )));
        }
    };
    let key = (problem.to_string(), t_end.to_bits());
    let cached = setups()
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .contains_key(&key);
    let point = Point {
        method,
        value,
        max_steps,
        repeats,
        key,
    };
    // A cached setup is reused (with_setup still builds the system, but
    // without its reference when one is cached).
    let row = py
        .detach(|| plan::with_setup(b, t_end, !cached, point))
        .map_err(|e| Fail::Problem(e.to_string()))??;
    row_to_py(py, &row)
}
