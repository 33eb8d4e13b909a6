//! `symlab.Problem`: a problem written in Python as NumPy-vectorised
//! callables, stepped by the Rust schemes. A separable Hamiltonian gives
//! `force(q)` and `velocity(p)` (and `potential`, `kinetic` for its
//! energy); any other ODE gives `rhs(t, y)`. Each call copies the state
//! into a new float64 array (a few doubles; the array must outlive the call
//! while Rust's slice does not) and reads the result back.
//!
//! A callable that raises, or returns the wrong shape or dtype, cannot
//! unwind through the Rust stepper: its error is kept, the output filled
//! with NaN so that the run stops at that step as diverged, and the caller
//! raises the kept error naming the callable.

use std::sync::{Arc, Mutex};

use compare::{AsOde, AsSeparable, Defaults, Problem as CmpProblem, StackSizes};
use integrator_core::{OdeSystem, Separable};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::errors::ProblemError;

/// The callables of a problem.
pub enum Callables {
    Separable {
        force: Py<PyAny>,
        velocity: Option<Py<PyAny>>,
        potential: Option<Py<PyAny>>,
        kinetic: Option<Py<PyAny>>,
    },
    Ode {
        rhs: Py<PyAny>,
        energy: Option<Py<PyAny>>,
    },
}

/// A problem given from Python.
pub struct Spec {
    pub name: String,
    /// Degrees of freedom (separable) or the state length (ODE), per
    /// initial condition.
    pub n: usize,
    pub callables: Callables,
    pub y0: Option<Vec<f64>>,
    /// An array (the state at `t_end`) or a callable `(y0, t_end) -> array`.
    pub reference: Option<Py<PyAny>>,
    pub defaults: Option<Defaults>,
}

impl Spec {
    pub fn is_separable(&self) -> bool {
        matches!(self.callables, Callables::Separable { .. })
    }
    /// The state length per initial condition.
    pub fn dim(&self) -> usize {
        if self.is_separable() {
            2 * self.n
        } else {
            self.n
        }
    }
}

/// A problem written in Python: ``force(q)`` and ``velocity(p)`` for a
/// separable Hamiltonian ``H = T(p) + V(q)`` (with ``potential(q)`` and
/// ``kinetic(p)`` for its energy; ``velocity`` defaults to ``p``), or
/// ``rhs(t, y)`` (and optionally ``energy(y)``) for any ODE. The callables
/// are NumPy-vectorised: given float64 arrays of shape ``(..., dof)`` they
/// return float64 arrays of the same shape (energies: shape ``(...)``), so
/// that an ensemble steps in one call per stage.
///
/// ``y0`` is the default start; ``reference`` the state at ``t_end`` (an
/// array, or a callable ``(y0, t_end) -> array``) for comparisons;
/// ``t_end``, ``h_min`` and ``h_max`` the defaults of a sweep.
///
/// >>> import numpy as np, symlab
/// >>> osc = symlab.Problem("osc", dof=1, force=lambda q: -q,
/// ...                      potential=lambda q: 0.5 * (q * q).sum(-1),
/// ...                      kinetic=lambda p: 0.5 * (p * p).sum(-1))
/// >>> t, y = symlab.integrate("stormer-verlet", osc, [1.0, 0.0], 0.0, 0.01, 100)
/// >>> y.shape
/// (2, 2)
#[pyclass(module = "symlab", frozen)]
pub struct Problem {
    pub spec: Arc<Spec>,
}

fn callable(py: Python<'_>, what: &str, f: Option<Py<PyAny>>) -> PyResult<Option<Py<PyAny>>> {
    match f {
        Some(f) if !f.bind(py).is_callable() => Err(PyTypeError::new_err(format!(
            "{what} must be callable, got {}",
            f.bind(py).get_type().name()?
        ))),
        f => Ok(f),
    }
}

#[pymethods]
impl Problem {
    #[new]
    #[pyo3(signature = (name, *, dof = None, dim = None, force = None, velocity = None,
                        potential = None, kinetic = None, rhs = None, energy = None,
                        y0 = None, reference = None, t_end = None, h_min = None, h_max = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        name: String,
        dof: Option<usize>,
        dim: Option<usize>,
        force: Option<Py<PyAny>>,
        velocity: Option<Py<PyAny>>,
        potential: Option<Py<PyAny>>,
        kinetic: Option<Py<PyAny>>,
        rhs: Option<Py<PyAny>>,
        energy: Option<Py<PyAny>>,
        y0: Option<Vec<f64>>,
        reference: Option<Py<PyAny>>,
        t_end: Option<f64>,
        h_min: Option<f64>,
        h_max: Option<f64>,
    ) -> PyResult<Self> {
        let force = callable(py, "force", force)?;
        let velocity = callable(py, "velocity", velocity)?;
        let potential = callable(py, "potential", potential)?;
        let kinetic = callable(py, "kinetic", kinetic)?;
        let rhs = callable(py, "rhs", rhs)?;
        let energy = callable(py, "energy", energy)?;
        let (n, callables) = match (force, rhs) {
            (Some(force), None) => {
                if energy.is_some() {
                    return Err(PyValueError::new_err(
                        "energy: a separable problem's energy is potential(q) + kinetic(p); give those",
                    ));
                }
                let Some(n) = dof else {
                    return Err(PyValueError::new_err(
                        "dof: a separable problem (force=...) needs its number of degrees of freedom",
                    ));
                };
                (
                    n,
                    Callables::Separable {
                        force,
                        velocity,
                        potential,
                        kinetic,
                    },
                )
            }
            (None, Some(rhs)) => {
                if velocity.is_some() || potential.is_some() || kinetic.is_some() {
                    return Err(PyValueError::new_err(
                        "rhs: velocity, potential and kinetic belong to a separable problem (force=...), not to rhs=...",
                    ));
                }
                let Some(n) = dim else {
                    return Err(PyValueError::new_err(
                        "dim: an ODE problem (rhs=...) needs the length of its state",
                    ));
                };
                (n, Callables::Ode { rhs, energy })
            }
            (Some(_), Some(_)) => {
                return Err(PyValueError::new_err(
                    "force, rhs: give force (a separable Hamiltonian) or rhs (any ODE), not both",
                ));
            }
            (None, None) => {
                return Err(PyValueError::new_err(
                    "force, rhs: give force=... (with velocity, potential, kinetic) or rhs=...",
                ));
            }
        };
        if n == 0 {
            return Err(PyValueError::new_err(
                "dof/dim: the state needs at least one component",
            ));
        }
        let spec = Spec {
            name,
            n,
            callables,
            y0: None,
            reference,
            defaults: None,
        };
        let dim = spec.dim();
        let y0 = match y0 {
            Some(v) if v.len() != dim => {
                return Err(PyValueError::new_err(format!(
                    "y0: expected {dim} components ({}), got {}",
                    if spec.is_separable() {
                        "q then p"
                    } else {
                        "the state"
                    },
                    v.len()
                )));
            }
            Some(v) => {
                if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                    return Err(PyValueError::new_err(format!(
                        "y0[{i}] is {}, not a finite number",
                        v[i]
                    )));
                }
                Some(v)
            }
            None => None,
        };
        let defaults = match (t_end, h_min, h_max) {
            (None, None, None) => None,
            (Some(t), Some(lo), Some(hi)) => Some(Defaults {
                t_end: t,
                h_min: lo,
                h_max: hi,
            }),
            _ => {
                return Err(PyValueError::new_err(
                    "t_end, h_min, h_max: give all three (the defaults of a sweep) or none",
                ));
            }
        };
        Ok(Problem {
            spec: Arc::new(Spec {
                y0,
                defaults,
                ..spec
            }),
        })
    }

    #[getter]
    fn name(&self) -> String {
        self.spec.name.clone()
    }

    /// The length of the state ``y`` (``2 * dof`` for a separable problem).
    #[getter]
    fn dim(&self) -> usize {
        self.spec.dim()
    }

    fn __repr__(&self) -> String {
        format!(
            "symlab.Problem({:?}, {} = {})",
            self.spec.name,
            if self.spec.is_separable() {
                "dof"
            } else {
                "dim"
            },
            self.spec.n
        )
    }
}

/// The first error a callable raised in a run (shared by every copy of
/// the system, since the comparisons step a copy).
pub type ErrorSlot = Arc<Mutex<Option<PyErr>>>;

/// A Python problem as a Rust system: `batch` initial conditions stacked
/// (`[q₁…q_m, p₁…p_m]` for a separable problem, each `q` of length dof;
/// `[y₁…y_m]` otherwise), each callable called once per evaluation with an
/// array of shape `(batch, n)` (or `(n,)` when `batch` is 1).
#[derive(Clone)]
pub struct PySystem {
    pub spec: Arc<Spec>,
    pub batch: usize,
    /// Added to the time given to `rhs` (a run that starts at `t0`).
    pub t0: f64,
    pub error: ErrorSlot,
}

impl PySystem {
    pub fn new(spec: Arc<Spec>, batch: usize, t0: f64) -> Self {
        PySystem {
            spec,
            batch,
            t0,
            error: Arc::new(Mutex::new(None)),
        }
    }

    pub fn take_error(&self) -> Option<PyErr> {
        self.error.lock().ok().and_then(|mut e| e.take())
    }

    fn failed(&self) -> bool {
        self.error.lock().map(|e| e.is_some()).unwrap_or(true)
    }

    fn keep(&self, e: PyErr) {
        if let Ok(mut slot) = self.error.lock()
            && slot.is_none()
        {
            *slot = Some(e);
        }
    }

    fn shape(&self) -> Vec<usize> {
        if self.batch == 1 {
            vec![self.spec.n]
        } else {
            vec![self.batch, self.spec.n]
        }
    }

    /// `out = f(x)` (or `f(t, x)`), `x` and `out` of `batch · n` doubles.
    fn call_into(&self, what: &str, f: &Py<PyAny>, t: Option<f64>, x: &[f64], out: &mut [f64]) {
        if self.failed() {
            out.fill(f64::NAN);
            return;
        }
        let r = Python::attach(|py| -> PyResult<()> {
            let arr = PyArray1::from_slice(py, x);
            let arr = arr.reshape(self.shape())?;
            let result = match t {
                Some(t) => f.call1(py, (t, arr)),
                None => f.call1(py, (arr,)),
            }
            .map_err(|e| {
                let err = ProblemError::new_err(format!(
                    "{what} raised {}",
                    e.get_type(py)
                        .name()
                        .map(|n| n.to_string())
                        .unwrap_or_default()
                ));
                err.set_cause(py, Some(e));
                err
            })?;
            let bound = result.bind(py);
            let expected = self.shape();
            let arr: PyReadonlyArrayDyn<'_, f64> = bound.extract().map_err(|_| {
                let got = match bound.getattr("dtype") {
                    Ok(d) => format!("an array of dtype {}", d),
                    Err(_) => bound
                        .get_type()
                        .name()
                        .map(|n| n.to_string())
                        .unwrap_or_default(),
                };
                ProblemError::new_err(format!(
                    "{what} must return a float64 NumPy array of shape {expected:?}, got {got}"
                ))
            })?;
            if arr.shape() != expected.as_slice() {
                return Err(ProblemError::new_err(format!(
                    "{what} must return a float64 NumPy array of shape {expected:?}, got shape {:?}",
                    arr.shape()
                )));
            }
            match arr.as_slice() {
                Ok(s) => out.copy_from_slice(s),
                Err(_) => {
                    for (o, v) in out.iter_mut().zip(arr.as_array().iter()) {
                        *o = *v;
                    }
                }
            }
            Ok(())
        });
        if let Err(e) = r {
            self.keep(e);
            out.fill(f64::NAN);
        }
    }

    /// A scalar-per-condition callable summed over the batch.
    fn call_sum(&self, what: &str, f: &Py<PyAny>, x: &[f64]) -> f64 {
        if self.failed() {
            return f64::NAN;
        }
        let r = Python::attach(|py| -> PyResult<f64> {
            let arr = PyArray1::from_slice(py, x).reshape(self.shape())?;
            let result = f.call1(py, (arr,)).map_err(|e| {
                let err = ProblemError::new_err(format!("{what} raised"));
                err.set_cause(py, Some(e));
                err
            })?;
            let np = py.import("numpy")?;
            let total = np.call_method1("sum", (result,))?;
            total.extract::<f64>().map_err(|_| {
                ProblemError::new_err(format!("{what} must return a float or float array"))
            })
        });
        r.unwrap_or_else(|e| {
            self.keep(e);
            f64::NAN
        })
    }
}

/// Separable problems: `z = [q; p]`.
#[derive(Clone)]
pub struct PySeparable(pub PySystem);

/// Any other ODE.
#[derive(Clone)]
pub struct PyOde(pub PySystem);

impl Separable for PySeparable {
    fn dof(&self) -> usize {
        self.0.batch * self.0.spec.n
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        match &self.0.spec.callables {
            Callables::Separable {
                kinetic: Some(k), ..
            } => self.0.call_sum("kinetic", k, p),
            _ => f64::NAN,
        }
    }
    fn potential(&self, q: &[f64]) -> f64 {
        match &self.0.spec.callables {
            Callables::Separable {
                potential: Some(v), ..
            } => self.0.call_sum("potential", v, q),
            _ => f64::NAN,
        }
    }
    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        match &self.0.spec.callables {
            Callables::Separable {
                velocity: Some(v), ..
            } => self.0.call_into("velocity", v, None, p, out),
            _ => out.copy_from_slice(p),
        }
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        if let Callables::Separable { force, .. } = &self.0.spec.callables {
            self.0.call_into("force", force, None, q, out)
        }
    }
}

impl OdeSystem for PyOde {
    fn dim(&self) -> usize {
        self.0.batch * self.0.spec.n
    }
    fn rhs(&self, t: f64, z: &[f64], dz: &mut [f64]) {
        if let Callables::Ode { rhs, .. } = &self.0.spec.callables {
            self.0.call_into("rhs", rhs, Some(t + self.0.t0), z, dz)
        }
    }
}

/// The reference end state from the spec: an array or a callable.
fn reference(sys: &PySystem, z0: &[f64], t_end: f64) -> Result<Vec<f64>, String> {
    let Some(r) = &sys.spec.reference else {
        return Err("reference: the problem has none (give reference=array or a callable (y0, t_end) -> array)".into());
    };
    Python::attach(|py| {
        let r = r.bind(py);
        let value = if r.is_callable() {
            r.call1((PyArray1::from_slice(py, z0), t_end))
                .map_err(|e| format!("reference raised: {e}"))?
        } else {
            r.clone()
        };
        let v: Vec<f64> = value
            .extract()
            .map_err(|_| "reference: expected a 1-D array of floats".to_string())?;
        if v.len() != z0.len() {
            return Err(format!(
                "reference: expected {} components (the state's length), got {}",
                z0.len(),
                v.len()
            ));
        }
        Ok(v)
    })
}

fn start(sys: &PySystem) -> Vec<f64> {
    sys.spec
        .y0
        .clone()
        .unwrap_or_else(|| vec![0.0; sys.spec.dim()])
}

fn defaults(sys: &PySystem) -> Defaults {
    sys.spec.defaults.unwrap_or(Defaults {
        t_end: 10.0,
        h_min: 1e-3,
        h_max: 0.1,
    })
}

impl CmpProblem for PySeparable {
    type Kind = AsSeparable;
    /// Slices: a Python callback costs far more than the step's loads and
    /// stores, and each stack size would compile every scheme again.
    const STACK_SIZES: StackSizes = StackSizes::NONE;
    /// Offered: the problem is the user's, maybe gravitational; a start with
    /// `V ≥ 0` is refused at step 0 as any `logh:` run's.
    const NEGATIVE_POTENTIAL: bool = true;
    fn name(&self) -> String {
        self.0.spec.name.clone()
    }
    fn energy(&self, z: &[f64]) -> f64 {
        integrator_core::energy(self, z)
    }
    fn start(&self) -> Vec<f64> {
        start(&self.0)
    }
    fn reference(&self, z0: &[f64], t_end: f64) -> Result<Vec<f64>, String> {
        reference(&self.0, z0, t_end)
    }
    fn defaults(&self) -> Defaults {
        defaults(&self.0)
    }
}

impl CmpProblem for PyOde {
    type Kind = AsOde;
    /// Slices: a Python callback costs far more than the step's loads and
    /// stores, and each stack size would compile every scheme again.
    const STACK_SIZES: StackSizes = StackSizes::NONE;
    fn name(&self) -> String {
        self.0.spec.name.clone()
    }
    fn energy(&self, z: &[f64]) -> f64 {
        match &self.0.spec.callables {
            Callables::Ode {
                energy: Some(e), ..
            } => self.0.call_sum("energy", e, z),
            _ => f64::NAN,
        }
    }
    fn start(&self) -> Vec<f64> {
        start(&self.0)
    }
    fn reference(&self, z0: &[f64], t_end: f64) -> Result<Vec<f64>, String> {
        reference(&self.0, z0, t_end)
    }
    fn defaults(&self) -> Defaults {
        defaults(&self.0)
    }
}
