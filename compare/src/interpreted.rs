//! Table files in the comparisons: read with a size limit, every claim
//! verified exactly (as `symlab check` and `butcher!` do), then stepped by
//! the run-time interpreters.
//!
//! All three kinds of table file are read ([`tableau::algebraic::file`]):
//! ordinary table files, generated tables (`generate = "gauss(8)"`) and
//! tables with `root(...)` entries. Their claims are checked by the same
//! exact analysis as `symlab check`'s, and a file with a false claim is
//! refused, naming the claim and the evidence.
//!
//! The coefficients of an ordinary table file are rounded exactly as
//! `butcher!` rounds them ([`tableau::rounding::round_table`] with the
//! table's analysis), those of a generated table are `tableau`'s certified
//! rounding (the constants of `butcher! { from: "gauss8" }`), and those of a
//! `root(...)` table the correctly rounded doubles of its exact entries
//! ([`tableau::algebraic::alg::Field::to_f64`]), as `butcher!` emits them.
//! So an interpreted table takes the same steps as the generated scheme of
//! the same table up to the order of floating-point operations: its errors
//! and evaluation counts compare with generated code. Its wall times do
//! not — explicit tables are stepped by loops over the table held in memory
//! ([`RkInterpreter`], [`SplittingInterpreter`]) instead of unrolled code —
//! so its rows are marked `interpreted`. Implicit tables and partitioned
//! pairs go to the same stage solver as the generated schemes, with the
//! table as data instead of a constant.

use std::path::{Path, PathBuf};

use integrator_core::implicit::{self, ImplicitTable, ImplicitWorkspace};
use integrator_core::interp::{RkInterpreter, SplittingInterpreter};
use integrator_core::{OdeSystem, SolveError, Step};
use tableau::Table;
use tableau::algebraic::file::{AlgAnalysis, AlgFile};
use tableau::algebraic::generated::{Generated, GeneratedTable};
use tableau::analysis::{Analysis, Class};
use tableau::claims::Claim;
use tableau::file::TableFile;
use tableau::rounding::{F64Pair, F64Rounded, F64Table, round_table};
use tableau::verdict::{Analysed, Options, Source, Verdict};

use crate::counting::{AsOde, AsSeparable};
use crate::error::{CompareError, Result};
use crate::method::{Fixed, Method};
use crate::problem::{ByKind, Family, Kind, Problem};
use crate::stepper::{StepStepper, Stepper};

/// The most stages of an implicit table or pair the interpreter steps (the
/// stage solver is generic over the stage count; these are instantiated).
pub const MAX_IMPLICIT_STAGES: usize = 16;

/// A table file whose claims all hold.
#[derive(Clone, Debug)]
pub struct VerifiedTable {
    pub path: PathBuf,
    /// The method id: the file name without its extension.
    pub id: String,
    /// What the file holds, with its exact analysis.
    pub form: VerifiedForm,
}

/// The three kinds of table file, each with what was decided about it.
#[derive(Clone, Debug)]
pub enum VerifiedForm {
    /// An ordinary table file (entries in rationals and radicals).
    Classic {
        file: Box<TableFile>,
        analysis: Box<Analysis>,
    },
    /// `generate = "gauss(8)"`: verdicts, claims and certified coefficients.
    Generated(Box<Generated>),
    /// Entries with `root(...)`: the symplecticity verdict and `B(k)`,
    /// and the coefficients as correctly rounded doubles.
    Algebraic {
        file: Box<AlgFile>,
        analysis: Box<AlgAnalysis>,
        coefficients: Box<RootCoefficients>,
    },
}

/// The `f64` form of a table with `root(...)` entries.
#[derive(Clone, Debug)]
pub struct RootCoefficients {
    /// `A`, `b` and `c` (the given `c`, else the exact row sums), each
    /// entry the correctly rounded double of its exact value.
    pub table: F64Table,
    /// For a pair: `q` (the table above) and `p` (`a_hat`, `b_hat`,
    /// `c_hat` or the row sums of `a_hat`), rounded in the same way.
    pub pair: Option<F64Pair>,
    /// `aᵢⱼ = 0` for every `j ≥ i`, decided exactly (never for a pair).
    pub explicit: bool,
    /// The order proven for the table: the conditions decided for root
    /// tables are `B(k)` (and `c` = row sums), so this is at most 2 (order
    /// 1: Σbᵢ = 1; order 2: also Σbᵢcᵢ = 1/2 with c the row sums; for a
    /// pair at most 1).
    pub order: usize,
}

/// The coefficients and the structure of a table with `root(...)` entries,
/// exactly: every double is the correctly rounded exact entry, and the
/// zero pattern of `A` is decided by exact zero tests. A pair (`a_hat`,
/// `b_hat`) gives its `p` table as well. `tableau`'s
/// [`round_root_table`](tableau::algebraic::rounded::round_root_table)
/// decides all of it, as for `butcher!`, which steps the same table.
pub fn root_coefficients(
    f: &AlgFile,
    an: &AlgAnalysis,
) -> std::result::Result<RootCoefficients, String> {
    let rounded = tableau::algebraic::rounded::round_root_table(f, an)?;
    Ok(RootCoefficients {
        pair: rounded.hat.map(|p| F64Pair {
            q: rounded.table.clone(),
            p,
        }),
        table: rounded.table,
        explicit: rounded.class == tableau::analysis::Class::Explicit,
        order: rounded.order,
    })
}

/// What the interpreters step: an ordinary table (rounded here as
/// `butcher!` rounds it) or coefficients already rounded by `tableau`.
#[derive(Clone, Copy, Debug)]
pub enum Interpretable<'a> {
    Table(&'a Table),
    /// A Runge–Kutta table in `f64`, with its structure decided exactly.
    Rk {
        table: &'a F64Table,
        explicit: bool,
    },
    /// A partitioned pair in `f64` (`q`: `A, b`; `p`: `Â, b̂`), implicit.
    Pair(&'a F64Pair),
    /// A processed method: the kernel (a drift–kick sequence or a
    /// composition) with its corrector `χ`, stepped as `χ Kⁿ χ⁻¹`
    /// ([`crate::processed`]).
    Processed {
        kernel: &'a Table,
        corrector: &'a tableau::Splitting,
    },
}

fn file_error(path: &Path, why: impl Into<String>) -> CompareError {
    CompareError::TableFile {
        path: path.to_path_buf(),
        why: why.into(),
    }
}

/// Read a table file of any kind and verify every claim it makes, exactly,
/// with the analysis `symlab check` runs ([`tableau::verdict`]). A file
/// that does not parse is an error naming the field; a claim that fails is
/// an error naming the claim and the evidence (every failing claim is
/// listed).
pub fn verify(path: &Path) -> Result<VerifiedTable> {
    let verdict = tableau::verdict::check(&Source::File(path), &Options::default())?;
    let id = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "table".into());
    VerifiedTable::from_verdict(path.to_path_buf(), id, verdict)
        .map_err(|why| file_error(path, why.to_string()))
}

/// Why a verdict is not a table the comparisons step.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Unverified {
    /// Claims that do not hold, each with its evidence.
    #[error("{}", .0.join("; "))]
    Claims(Vec<String>),
    /// A `root(...)` table whose doubles could not be decided (beyond a
    /// budget).
    #[error("{0}")]
    Coefficients(String),
}

impl VerifiedTable {
    /// A verdict whose claims all hold, as a table the interpreters step
    /// (`path` and `id` name it); otherwise every failing claim, with its
    /// evidence. A `root(...)` table's coefficients are rounded here.
    pub fn from_verdict(
        path: PathBuf,
        id: String,
        verdict: Verdict,
    ) -> std::result::Result<VerifiedTable, Unverified> {
        let failed = verdict.failed_claims();
        if !failed.is_empty() {
            return Err(Unverified::Claims(failed));
        }
        let form = match verdict.analysed {
            Analysed::Classic { file, analysis, .. } => VerifiedForm::Classic { file, analysis },
            Analysed::Generated(g) => VerifiedForm::Generated(g),
            Analysed::Algebraic { file, analysis } => {
                let coefficients =
                    root_coefficients(&file, &analysis).map_err(Unverified::Coefficients)?;
                VerifiedForm::Algebraic {
                    file,
                    analysis,
                    coefficients: Box::new(coefficients),
                }
            }
        };
        Ok(VerifiedTable { path, id, form })
    }
}

/// The classical order a file claims: `order = p`, with a residual bound
/// or certified (a certified order is that of an exact method within the
/// certificate's radius of the printed coefficients, so the doubles step
/// with order `p` down to round-off, as rounded exact tables do).
fn claimed_order(claims: &[Claim]) -> Option<usize> {
    claims.iter().find_map(|c| match c {
        Claim::Order { p, .. } | Claim::CertifiedOrder { p } => Some(*p),
        _ => None,
    })
}

impl<P: Problem> Method<P> {
    /// A verified table file as a method, stepped by the interpreters; the
    /// id is the file name without its extension. Its order is the claimed
    /// order if the file claims one, else the verified order (on separable
    /// systems for forms that step only those; for a `root(...)` table the
    /// order its decided conditions prove, at most 2).
    pub fn table_file(path: &Path) -> Result<Self> {
        Self::interpreted(&verify(path)?)
    }

    /// A verified table as a method (see [`table_file`](Method::table_file)).
    pub fn interpreted(t: &VerifiedTable) -> Result<Self> {
        let (what, order, symplectic, family) = match &t.form {
            VerifiedForm::Classic { file, analysis: a } if file.corrector.is_some() => {
                // The claims are the effective method's (checked so by
                // `verify`); its classical order is the last entry of a
                // generalised one. Unclaimed, the kernel's order: `χ K χ⁻¹`
                // is conjugate to `K`, so it has at least that order.
                let order =
                    file.claims
                        .iter()
                        .find_map(|c| match c {
                            Claim::Order { p, .. } | Claim::CertifiedOrder { p } => Some(*p),
                            Claim::NearOrder { orders, .. }
                            | Claim::CertifiedNearOrder { orders } => orders.last().copied(),
                            _ => None,
                        })
                        .unwrap_or(a.claimed_order_report().order);
                let symplectic =
                    crate::method::symplectic_for::<P>(a.symplectic, a.symplectic_separable);
                let corrector = file.corrector.as_ref().expect("matched on is_some");
                (
                    Interpretable::Processed {
                        kernel: &file.table,
                        corrector,
                    },
                    order,
                    symplectic,
                    Family::Splitting,
                )
            }
            VerifiedForm::Classic { file, analysis: a } => {
                let order = claimed_order(&file.claims).unwrap_or(a.claimed_order_report().order);
                let family = if !a.explicit_separable {
                    Family::Implicit
                } else if matches!(file.table, Table::Rk(_)) {
                    Family::ExplicitRk
                } else {
                    Family::Splitting
                };
                let symplectic =
                    crate::method::symplectic_for::<P>(a.symplectic, a.symplectic_separable);
                (Interpretable::Table(&file.table), order, symplectic, family)
            }
            VerifiedForm::Generated(g) => {
                let what = match &g.f64_table {
                    GeneratedTable::Rk(table) => Interpretable::Rk {
                        table,
                        explicit: false,
                    },
                    GeneratedTable::Prk(pair) => Interpretable::Pair(pair),
                };
                let claims: Vec<Claim> = g.claims.iter().map(|(c, _)| c.clone()).collect();
                let order = claimed_order(&claims).unwrap_or(g.proven_order());
                (what, order, g.symplectic, Family::Implicit)
            }
            VerifiedForm::Algebraic {
                analysis,
                coefficients: k,
                ..
            } => {
                let what = match &k.pair {
                    Some(pair) => Interpretable::Pair(pair),
                    None => Interpretable::Rk {
                        table: &k.table,
                        explicit: k.explicit,
                    },
                };
                let family = if k.explicit {
                    Family::ExplicitRk
                } else {
                    Family::Implicit
                };
                let symplectic = crate::method::symplectic_for::<P>(
                    analysis.symplectic == Some(true),
                    analysis.symplectic_separable == Some(true),
                );
                (what, k.order, symplectic, family)
            }
        };
        let stepper = stepper_for::<P>(what, &t.id)?;
        Ok(Method::Fixed(Fixed {
            id: t.id.clone(),
            order,
            symplectic,
            family,
            interpreted: true,
            stepper,
        }))
    }
}

/// An implicit table (or any pair) as data for the stage solver.
struct Implicit<const S: usize>(ImplicitTable<S>);

impl<Sys: OdeSystem + ?Sized, const S: usize> Step<Sys> for Implicit<S> {
    type Workspace = ImplicitWorkspace;
    fn workspace(&self, sys: &Sys) -> ImplicitWorkspace {
        ImplicitWorkspace::new(sys.dim(), S)
    }
    fn step(
        &self,
        sys: &Sys,
        t: f64,
        h: f64,
        z: &mut [f64],
        ws: &mut ImplicitWorkspace,
    ) -> std::result::Result<(), SolveError> {
        implicit::step(&self.0, sys, t, h, z, ws)
    }
}

fn square<const S: usize>(a: &[Vec<f64>]) -> [[f64; S]; S] {
    std::array::from_fn(|i| std::array::from_fn(|j| a[i][j]))
}

fn row<const S: usize>(v: &[f64]) -> [f64; S] {
    std::array::from_fn(|i| v[i])
}

fn implicit_of<P: Problem, const S: usize>(
    q: &F64Table,
    p: Option<&F64Table>,
) -> Box<dyn Stepper<P>> {
    let table = match p {
        None => ImplicitTable::new(square::<S>(&q.a), row::<S>(&q.b), row::<S>(&q.c)),
        Some(p) => ImplicitTable::partitioned(
            square::<S>(&q.a),
            row::<S>(&q.b),
            square::<S>(&p.a),
            row::<S>(&p.b),
            row::<S>(&q.c),
        ),
    };
    Box::new(StepStepper(Implicit(table)))
}

/// The stage solver for `q` (and `p` for a pair), instantiated for the
/// table's stage count.
fn implicit_stepper<P: Problem>(
    q: &F64Table,
    p: Option<&F64Table>,
    id: &str,
) -> Result<Box<dyn Stepper<P>>> {
    macro_rules! dispatch {
        ($($s:literal)*) => {
            match q.b.len() {
                $($s => Ok(implicit_of::<P, $s>(q, p)),)*
                s => Err(CompareError::method(
                    id,
                    format!(
                        "table '{id}' has {s} stages; the interpreter steps implicit tables and pairs of at most {MAX_IMPLICIT_STAGES} stages"
                    ),
                )),
            }
        };
    }
    dispatch!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
}

fn analysis_error(id: &str, e: impl std::fmt::Display) -> CompareError {
    CompareError::method(id, format!("table '{id}': {e}"))
}

/// A Runge–Kutta table on any problem.
fn rk<P: Problem>(what: Interpretable<'_>, id: &str) -> Result<Box<dyn Stepper<P>>> {
    let pair_refused = |form: &str| {
        CompareError::method(
            id,
            format!(
                "table '{id}' is a {form}: it steps separable Hamiltonians H = T(p) + V(q) only, and this problem \
                 is an OdeSystem only; a Runge–Kutta table (a and b alone) steps it"
            ),
        )
    };
    match what {
        Interpretable::Table(table) => {
            let Table::Rk(_) = table else {
                return Err(pair_refused(form_words(table)));
            };
            let analysis = Analysis::of(table).map_err(|e| analysis_error(id, e))?;
            match round_table(table, &analysis) {
                F64Rounded::Rk(t) => f64_rk::<P>(&t, analysis.class == Class::Explicit, id),
                _ => unreachable!("a Runge–Kutta table rounds to one"),
            }
        }
        Interpretable::Rk { table, explicit } => f64_rk::<P>(table, explicit, id),
        Interpretable::Pair(_) => Err(pair_refused("partitioned pair")),
        Interpretable::Processed { .. } => Err(pair_refused(
            "processed method (a kernel with a corrector, stepped χ Kⁿ χ⁻¹)",
        )),
    }
}

/// A Runge–Kutta table in `f64`: explicit ones by the loop interpreter,
/// the others by the stage solver.
fn f64_rk<P: Problem>(t: &F64Table, explicit: bool, id: &str) -> Result<Box<dyn Stepper<P>>> {
    if explicit {
        Ok(Box::new(StepStepper(
            RkInterpreter::new(t.a.clone(), t.b.clone(), t.c.clone())
                .map_err(|e| analysis_error(id, e))?,
        )))
    } else {
        implicit_stepper::<P>(t, None, id)
    }
}

/// A table as a stepper of `P`, or why it cannot step `P`: any form on a
/// separable problem, Runge–Kutta tables on any other.
fn stepper_for<P: Problem>(what: Interpretable<'_>, id: &str) -> Result<Box<dyn Stepper<P>>> {
    struct Interpret<'a, 'b>(Interpretable<'a>, &'b str);
    impl<P: Problem> ByKind<P> for Interpret<'_, '_> {
        type Output = Result<Box<dyn Stepper<P>>>;
        fn separable(self) -> Self::Output
        where
            P: Problem<Kind = AsSeparable> + integrator_core::Separable,
        {
            separable(self.0, self.1)
        }
        fn ode(self) -> Self::Output
        where
            P: Problem<Kind = AsOde>,
        {
            rk(self.0, self.1)
        }
    }
    <P::Kind as Kind<P>>::by_kind(Interpret(what, id))
}

/// Any table on a separable problem.
fn separable<P>(what: Interpretable<'_>, id: &str) -> Result<Box<dyn Stepper<P>>>
where
    P: Problem<Kind = AsSeparable> + integrator_core::Separable,
{
    let table = match what {
        Interpretable::Table(table) => table,
        Interpretable::Rk { .. } => return rk(what, id),
        Interpretable::Pair(pair) => return implicit_stepper::<P>(&pair.q, Some(&pair.p), id),
        Interpretable::Processed { kernel, corrector } => {
            return crate::processed::processed(kernel, corrector)
                .map(|m| Box::new(m) as Box<dyn Stepper<P>>)
                .map_err(|e| analysis_error(id, e));
        }
    };
    match table {
        Table::Rk(_) => rk(what, id),
        Table::Splitting(_) | Table::Composition(_) => Ok(Box::new(StepStepper(
            SplittingInterpreter::from_table(table).map_err(|e| analysis_error(id, e))?,
        ))),
        Table::Prk(_) => {
            let analysis = Analysis::of(table).map_err(|e| analysis_error(id, e))?;
            match round_table(table, &analysis) {
                F64Rounded::Prk(pair) => implicit_stepper::<P>(&pair.q, Some(&pair.p), id),
                _ => unreachable!("a pair rounds to a pair"),
            }
        }
    }
}

fn form_words(t: &Table) -> &'static str {
    match t {
        Table::Rk(_) => "Runge–Kutta table",
        Table::Prk(_) => "partitioned pair",
        Table::Splitting(s) if s.has_gradient() => "drift–kick sequence with gradient kicks",
        Table::Splitting(_) => "drift–kick sequence",
        Table::Composition(_) => "composition",
    }
}
