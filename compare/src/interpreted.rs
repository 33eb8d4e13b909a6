//! Table files in the comparisons: read with a size limit, every claim
//! verified exactly (as `symlab check` and `butcher!` do), then stepped by
//! the run-time interpreters.
//!
//! The coefficients are rounded exactly as `butcher!` rounds them
//! ([`tableau::rounding::round_table`] with the table's analysis), so an
//! interpreted table takes the same steps as the generated scheme of the
//! same table up to the order of floating-point operations: its errors and
//! evaluation counts compare with generated code. Its wall times do not —
//! explicit tables are stepped by loops over the table held in memory
//! ([`RkInterpreter`], [`SplittingInterpreter`]) instead of unrolled code —
//! so its rows are marked `interpreted`. Implicit tables and partitioned
//! pairs go to the same stage solver as the generated schemes, with the
//! table as data instead of a constant.

use std::io::Read;
use std::path::{Path, PathBuf};

use integrator_core::implicit::{self, ImplicitTable, ImplicitWorkspace};
use integrator_core::interp::{RkInterpreter, SplittingInterpreter};
use integrator_core::{OdeSystem, SolveError, Step};
use tableau::Table;
use tableau::analysis::{Analysis, Class, check_claim};
use tableau::claims::Claim;
use tableau::file::{TableFile, parse_table_file};
use tableau::rounding::{F64Rounded, F64Table, round_table};

use crate::error::{CompareError, Result};
use crate::method::{Fixed, Method};
use crate::problem::{Family, Kind, Problem};
use crate::stepper::{Lib, Stepper};

/// The largest table file read (a table of a hundred stages is far below).
pub const MAX_FILE_BYTES: u64 = 1 << 20;

/// The most stages of an implicit table or pair the interpreter steps (the
/// stage solver is generic over the stage count; these are instantiated).
pub const MAX_IMPLICIT_STAGES: usize = 16;

/// A table file whose claims all hold.
#[derive(Clone, Debug)]
pub struct VerifiedTable {
    pub path: PathBuf,
    /// The method id: the file name without its extension.
    pub id: String,
    pub file: TableFile,
    pub analysis: Analysis,
}

fn file_error(path: &Path, why: impl Into<String>) -> CompareError {
    CompareError::TableFile {
        path: path.to_path_buf(),
        why: why.into(),
    }
}

/// Read at most [`MAX_FILE_BYTES`] of a text file.
pub(crate) fn read_limited(path: &Path, limit: u64) -> std::result::Result<String, String> {
    let f = std::fs::File::open(path).map_err(|e| format!("cannot read the file: {e}"))?;
    let mut text = String::new();
    f.take(limit + 1)
        .read_to_string(&mut text)
        .map_err(|e| format!("cannot read the file: {e}"))?;
    if text.len() as u64 > limit {
        return Err(format!(
            "the file is larger than {limit} bytes; a table file is a few hundred bytes"
        ));
    }
    Ok(text)
}

/// Read a table file and verify every claim it makes, exactly. A file that
/// does not parse is an error naming the field; a claim that fails is an
/// error naming the claim and the evidence (every failing claim is listed).
pub fn verify(path: &Path) -> Result<VerifiedTable> {
    let text = read_limited(path, MAX_FILE_BYTES).map_err(|why| file_error(path, why))?;
    let file = parse_table_file(&path.display().to_string(), &text).map_err(|e| {
        file_error(
            path,
            match &e.field {
                Some(field) => format!("field {field}: {}", e.message),
                None => e.message.clone(),
            },
        )
    })?;
    let analysis = Analysis::of(&file.table).map_err(|e| file_error(path, format!("field {e}")))?;
    let failed: Vec<String> = file
        .claims
        .iter()
        .filter_map(|c| {
            check_claim(&file.table, &analysis, c)
                .err()
                .map(|e| format!("claim `{c}` does not hold: {e}"))
        })
        .collect();
    if !failed.is_empty() {
        return Err(file_error(path, failed.join("; ")));
    }
    let id = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "table".into());
    Ok(VerifiedTable {
        path: path.to_path_buf(),
        id,
        file,
        analysis,
    })
}

impl<P: Problem> Method<P> {
    /// A verified table file as a method, stepped by the interpreters; the
    /// id is the file name without its extension. Its order is the claimed
    /// order if the file claims one, else the verified order (on separable
    /// systems for forms that step only those).
    pub fn table_file(path: &Path) -> Result<Self> {
        Self::interpreted(&verify(path)?)
    }

    /// A verified table as a method (see [`table_file`](Method::table_file)).
    pub fn interpreted(t: &VerifiedTable) -> Result<Self> {
        let stepper = <P::Kind as Kind<P>>::interpreted(&t.file.table, &t.id)?;
        let a = &t.analysis;
        let order = t
            .file
            .claims
            .iter()
            .find_map(|c| match c {
                Claim::Order { p, .. } => Some(*p),
                _ => None,
            })
            .unwrap_or(a.claimed_order_report().order);
        let family = if !a.explicit_separable {
            Family::Implicit
        } else if matches!(t.file.table, Table::Rk(_)) {
            Family::ExplicitRk
        } else {
            Family::Splitting
        };
        Ok(Method::Fixed(Fixed {
            id: t.id.clone(),
            order,
            symplectic: crate::method::symplectic_for::<P>(a.symplectic, a.symplectic_separable),
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
    Box::new(Lib(Implicit(table)))
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
pub(crate) fn rk<P: Problem>(table: &Table, id: &str) -> Result<Box<dyn Stepper<P>>> {
    let Table::Rk(_) = table else {
        return Err(CompareError::method(
            id,
            format!(
                "table '{id}' is a {}: it steps separable Hamiltonians H = T(p) + V(q) only, and this problem \
                 is an OdeSystem only; a Runge–Kutta table (a and b alone) steps it",
                form_words(table)
            ),
        ));
    };
    let analysis = Analysis::of(table).map_err(|e| analysis_error(id, e))?;
    match round_table(table, &analysis) {
        F64Rounded::Rk(t) if analysis.class == Class::Explicit => Ok(Box::new(Lib(
            RkInterpreter::new(t.a, t.b, t.c).map_err(|e| analysis_error(id, e))?,
        ))),
        F64Rounded::Rk(t) => implicit_stepper::<P>(&t, None, id),
        _ => unreachable!("a Runge–Kutta table rounds to one"),
    }
}

/// Any table on a separable problem.
pub(crate) fn separable<P>(table: &Table, id: &str) -> Result<Box<dyn Stepper<P>>>
where
    P: Problem<Kind = crate::counting::AsSeparable> + integrator_core::Separable,
{
    match table {
        Table::Rk(_) => rk(table, id),
        Table::Splitting(_) | Table::Composition(_) => Ok(Box::new(Lib(
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
        Table::Splitting(_) => "drift–kick sequence",
        Table::Composition(_) => "composition",
    }
}
