//! The verdict on a table: one place that turns a source (a file, a
//! built-in id, a text) into everything decided about it, as the readable
//! report and as the JSON object of `symlab check` and `symlab.check`.
//!
//! The command line and the Python package are thin clients of this module:
//! they choose the source and print or convert the [`Verdict`]; neither
//! builds a field of the report. So the two give the same JSON for the same
//! table, field for field (a test runs both over every catalogue table,
//! generated table and root-entry file).
//!
//! ```
//! use tableau::verdict::{Options, Source, check};
//!
//! let v = check(&Source::Builtin("gauss2"), &Options::default()).unwrap();
//! let json = v.to_json();
//! assert_eq!(json["symplectic"], true);
//! assert_eq!(json["order"], 4);
//! assert!(v.to_string().contains("W = BA + AᵀB − bbᵀ = 0"));
//! assert!(v.failed_claims().is_empty());
//! ```
//!
//! # Phases
//! 1. [`resolve`]: read and parse the source and decide its kind once — an
//!    ordinary table file (rationals and radicals: Runge–Kutta tables,
//!    partitioned pairs, drift–kick sequences, compositions, processed
//!    methods), a generated collocation table (`generate = "gauss(8)"`,
//!    `--builtin gauss8`), or a table with real algebraic (`root(...)`)
//!    entries ([`crate::algebraic::file::Loaded`]). The shape of an ordinary
//!    table is checked here, so a malformed table is refused before any
//!    analysis.
//! 2. [`Verdict::of`]: the exact analysis of that kind, every claim decided,
//!    and for a table that claims generalised (h, ε) orders (or when
//!    [`Options::near_integrable`] asks) its orders for `H = A + εB`.
//! 3. [`Verdict::to_json`] and `Display`: the two renderings.
//!
//! [`check`] runs 1 and 2 on the analysis thread ([`on_analysis_thread`]),
//! whose stack is sized for the deepest entry the parser admits, and which
//! turns a panic of the analysis into an error instead of a crash.
//!
//! # The JSON object
//! Every kind has `origin` (how messages name the table: the file path,
//! `builtin:ID`), `name`, `kind` (`"rk"` or `"prk"`), `stages`,
//! `row_sums_ok`, `symplectic`, `symplectic_separable`, `claims` (a list of
//! `{claim, holds, reason}`: `reason` is the evidence when `holds` is false,
//! else null) and `report` (the readable report, the text `symlab check`
//! prints). Then, by kind:
//!
//! - **ordinary table**: the fields of design.md — `class`, `order`
//!   (null for a drift–kick sequence with gradient kicks), `order_separable`,
//!   `order_limit`, `order_rkn`, `symmetric`, `stability_function` (`R(z)`
//!   exactly, or null), `stability_not_computed` (why not, beyond a budget) —
//!   and `w_nonzero`, the entries of `W` that do not vanish, each
//!   `{i, j, value, value_f64}` (`value` exact). A processed method adds
//!   `processed` (`kernel`, `corrector_drift`, `corrector_kick`,
//!   `effective_flows`); a table whose generalised orders were decided adds
//!   `near_integrable` (`decided`; when decided `orders`, `exact`, `parts`
//!   with each part's `b_letters`, `order`, `limit` and `first_failure`
//!   (`word`, `lie`, `degree`, `value`, `value_f64`), `degrees`, `bound`,
//!   `words`, `conditions`, `ms`; when not, `reason` and `degrees`).
//! - **generated table**: `generator`, `node_polynomial`, `class`, `order`
//!   (null for a Lobatto IIIA–IIIB pair whose order is not proven),
//!   `order_upper`, `order_proof`, `order_proof_p`, `tree_order`,
//!   `tree_order_limit`, `symmetric`, `stability_function`, `a_stable`,
//!   `r_infinity`, `max_w_rounded`, `max_w_nearest`, `verify_ms`, `round_ms`.
//! - **root-entry table**: `entries` (`"algebraic"`), `roots` (the names of
//!   the `let` roots), `w_nonzero` as `{i, j, zero, value_f64}` (`zero`:
//!   true, false, or null beyond budget; both `(i, j)` and `(j, i)` of the
//!   symmetric `W`), `b_levels` (`B(k)` for k = 1, 2, …: true, false or null),
//!   for a pair `b_hat_levels`, and `refusals` (what was beyond a budget).
//!
//! The timings (`ms`, `verify_ms`, `round_ms`, and the `time` row of a
//! generated table's `report`) are all that differs between two runs on the
//! same table.

mod json;
mod near;
mod report;

use std::path::Path;

use crate::algebraic::file::{AlgAnalysis, AlgFile, Loaded};
use crate::algebraic::generated::Generated;
use crate::analysis::Analysis;
use crate::catalogue;
use crate::claims::Claim;
use crate::file::{FileError, TableFile};

pub use near::Near;

/// Where a table comes from.
#[derive(Clone, Copy, Debug)]
pub enum Source<'a> {
    /// A table file of any kind (at most
    /// [`crate::budget::MAX_FILE_BYTES`]); messages name its path.
    File(&'a Path),
    /// A catalogue id (`gauss2`, `yoshida4`), or a generated table
    /// (`gauss8`, `radau2a5`, `lobatto3a3b4`, `gauss(8)`). The catalogue's
    /// hand-written table wins where both exist (`gauss3`); `gauss(3)`, with
    /// parentheses, always generates. Messages name it `builtin:ID`.
    Builtin(&'a str),
    /// The text of a table file; messages name it `origin`.
    Text { origin: &'a str, text: &'a str },
}

impl Source<'_> {
    /// How messages name the table: the path, `builtin:ID`, the origin given.
    pub fn origin(&self) -> String {
        match *self {
            Source::File(path) => path.display().to_string(),
            Source::Builtin(id) => format!("builtin:{id}"),
            Source::Text { origin, .. } => origin.to_string(),
        }
    }
}

/// A source read and its kind decided.
#[derive(Clone, Debug)]
pub struct Resolved {
    /// How messages name the table: the path, `builtin:ID`, the origin given.
    pub origin: String,
    pub table: Loaded,
}

/// What can go wrong before a verdict exists. Every message names the
/// table (its path or `builtin:ID`) and, where there is one, the field.
#[derive(Debug, thiserror::Error)]
pub enum VerdictError {
    /// The file could not be read or parsed; names the file and field.
    #[error(transparent)]
    File(#[from] FileError),
    /// An unknown built-in id, a generator that cannot make its table, a
    /// table whose dimensions do not fit.
    #[error("{0}")]
    Input(String),
    /// A bug: the analysis of the table `origin` panicked (`what`: the
    /// panic's message). The message asks for a report.
    #[error(
        "{origin}: internal error: the analysis panicked ({what}); please report it with the table"
    )]
    Panicked { origin: String, what: String },
    /// The analysis thread could not be started.
    #[error("{origin}: cannot start the analysis thread: {why}")]
    Thread { origin: String, why: String },
}

impl VerdictError {
    /// A refusal by one of [`crate::budget`]'s limits (every such message
    /// names its constant), as opposed to malformed input.
    pub fn is_budget(&self) -> bool {
        self.to_string().contains("tableau::budget::")
    }
}

/// What to decide beyond what a table claims.
#[derive(Clone, Copy, Debug, Default)]
pub struct Options {
    /// Also decide the generalised orders (p₁, p₂, …) of a drift–kick
    /// sequence or composition for `H = A + εB` (drifts the flow of `A`,
    /// kicks that of `εB`). Done regardless for a table that claims them
    /// (`order = (8, 6, 4)`) and for a processed method.
    pub near_integrable: bool,
}

/// Read `source` and decide its kind; an ordinary table's shape is
/// checked. Runs on the calling thread: see [`check`] for the analysis
/// thread.
pub fn resolve(source: &Source<'_>) -> Result<Resolved, VerdictError> {
    let origin = source.origin();
    let table = match *source {
        Source::File(path) => crate::algebraic::file::load(path)?,
        Source::Text { origin, text } => crate::algebraic::file::parse(origin, text)?,
        Source::Builtin(id) => builtin(id)?,
    };
    if let Loaded::Classic(tf) = &table {
        tf.table
            .check_shape()
            .map_err(|e| VerdictError::Input(format!("{origin}: field {e}")))?;
    }
    Ok(Resolved { origin, table })
}

/// The catalogue's table of `id`, else a generated one.
fn builtin(id: &str) -> Result<Loaded, VerdictError> {
    let generator_syntax = id.contains('(');
    match catalogue::find(id) {
        Some(entry) if !generator_syntax => Ok(Loaded::Classic(Box::new(entry.load()?))),
        _ => match Generated::new(id) {
            Ok(g) => Ok(Loaded::Generated(Box::new(g))),
            Err(gen_err) if generator_syntax => {
                Err(VerdictError::Input(format!("builtin:{id}: {gen_err}")))
            }
            Err(gen_err) => match catalogue::load(id) {
                Err(e) if gen_err.contains("unknown generator") => Err(VerdictError::Input(
                    format!("{e} (or a generated table: gauss8, radau2a5, lobatto3a3b4, …)"),
                )),
                _ => Err(VerdictError::Input(format!("builtin:{id}: {gen_err}"))),
            },
        },
    }
}

/// One claim as written and its verdict: `Err` carries the evidence.
#[derive(Clone, Debug, PartialEq)]
pub struct ClaimVerdict {
    pub claim: String,
    pub verdict: Result<(), String>,
}

/// A table analysed, of whichever kind it is.
#[derive(Clone, Debug)]
pub enum Analysed {
    /// An ordinary table file (or catalogue table), with its generalised
    /// orders where they were decided.
    Classic {
        file: Box<TableFile>,
        analysis: Box<Analysis>,
        near: Option<Near>,
        /// The proof of a certified order claim (`order = p (certified)`)
        /// from the file's certificate, or why there is none.
        certificate: Option<Box<Result<crate::certificate::Proof, String>>>,
    },
    /// A generated table (verified when it was made).
    Generated(Box<Generated>),
    /// A table with `root(...)` entries.
    Algebraic {
        file: Box<AlgFile>,
        analysis: Box<AlgAnalysis>,
    },
}

/// Everything decided about one table.
#[derive(Clone, Debug)]
pub struct Verdict {
    /// How messages name the table.
    pub origin: String,
    pub analysed: Analysed,
    /// Every claim of the table, in its order, with its verdict.
    pub claims: Vec<ClaimVerdict>,
}

impl Verdict {
    /// Analyse a resolved table and decide its claims. Runs on the calling
    /// thread (whose stack must be as [`on_analysis_thread`]'s for hostile
    /// input).
    /// `origin` names the table in messages (as [`Resolved::origin`]).
    pub fn of(origin: &str, table: &Loaded, options: &Options) -> Result<Verdict, VerdictError> {
        let origin = origin.to_string();
        let (analysed, claims) = match table {
            Loaded::Classic(tf) => {
                let analysis = Analysis::of(&tf.table)
                    .map_err(|e| VerdictError::Input(format!("{origin}: field {e}")))?;
                // A certified order is proven once, for its claim and for
                // the report.
                let certified = tf.claims.iter().position(|c| {
                    matches!(
                        c,
                        Claim::CertifiedOrder { .. } | Claim::CertifiedNearOrder { .. }
                    )
                });
                let certificate = tf.certificate.as_ref().and_then(|spec| {
                    certified.map(|i| {
                        Box::new(match &tf.claims[i] {
                            Claim::CertifiedOrder { p } => crate::certificate::prove(spec, *p),
                            Claim::CertifiedNearOrder { orders } => {
                                crate::certificate::prove_orders(spec, orders, true)
                            }
                            _ => unreachable!("a certified claim"),
                        })
                    })
                });
                let claims = tf
                    .claims
                    .iter()
                    .enumerate()
                    .map(|(i, c)| ClaimVerdict {
                        claim: c.to_string(),
                        verdict: match certificate.as_deref() {
                            Some(r) if Some(i) == certified => {
                                r.as_ref().map(|_| ()).map_err(Clone::clone)
                            }
                            _ => crate::analysis::check_file_claim(tf, &analysis, c)
                                .map_err(|e| e.to_string()),
                        },
                    })
                    .collect();
                let near = near::decide(tf, options.near_integrable);
                (
                    Analysed::Classic {
                        file: tf.clone(),
                        analysis: Box::new(analysis),
                        near,
                        certificate,
                    },
                    claims,
                )
            }
            Loaded::Generated(g) => {
                let claims = g
                    .claims
                    .iter()
                    .map(|(c, v)| ClaimVerdict {
                        claim: c.to_string(),
                        verdict: v.as_ref().map_err(|e| e.to_string()).copied(),
                    })
                    .collect();
                (Analysed::Generated(g.clone()), claims)
            }
            Loaded::Algebraic(f) => {
                let analysis = f.analyse();
                let claims = f
                    .claims
                    .iter()
                    .map(|c| ClaimVerdict {
                        claim: c.to_string(),
                        verdict: f.check_claim(&analysis, c),
                    })
                    .collect();
                (
                    Analysed::Algebraic {
                        file: f.clone(),
                        analysis: Box::new(analysis),
                    },
                    claims,
                )
            }
        };
        Ok(Verdict {
            origin,
            analysed,
            claims,
        })
    }

    /// The table's `name`.
    pub fn name(&self) -> &str {
        match &self.analysed {
            Analysed::Classic { file, .. } => &file.name,
            Analysed::Generated(g) => &g.name,
            Analysed::Algebraic { file, .. } => &file.name,
        }
    }

    /// Each claim that does not hold, said as `claim `C` does not hold:
    /// EVIDENCE` (the words of `compare --table` and of Python's
    /// `ClaimError`).
    pub fn failed_claims(&self) -> Vec<String> {
        self.claims
            .iter()
            .filter_map(|c| {
                c.verdict
                    .as_ref()
                    .err()
                    .map(|e| format!("claim `{}` does not hold: {e}", c.claim))
            })
            .collect()
    }

    /// The JSON object (the fields are listed in the module's documentation).
    pub fn to_json(&self) -> serde_json::Value {
        json::verdict(self)
    }
}

/// The readable report, as `symlab check` prints it.
impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&report::verdict(self))
    }
}

/// The stack of the thread that reads and analyses a table. The analysis
/// recurses only as deep as an entry is nested (at most
/// [`crate::expr::MAX_DEPTH`] levels), and every collocation table with
/// s ≤ 8 written with `root(...)` entries is checked on a 2 MiB stack in the
/// debug build; 16 MiB is margin.
pub const ANALYSIS_STACK_BYTES: usize = 16 << 20;

/// Run `f` on a thread of [`ANALYSIS_STACK_BYTES`], and turn a panic of it
/// into [`VerdictError::Panicked`] naming `origin` instead of a crash.
pub fn on_analysis_thread<T: Send>(
    origin: &str,
    f: impl FnOnce() -> Result<T, VerdictError> + Send,
) -> Result<T, VerdictError> {
    std::thread::scope(|scope| {
        let worker = std::thread::Builder::new()
            .name("tableau-verdict".into())
            .stack_size(ANALYSIS_STACK_BYTES)
            .spawn_scoped(scope, f)
            .map_err(|e| VerdictError::Thread {
                origin: origin.to_string(),
                why: e.to_string(),
            })?;
        worker.join().unwrap_or_else(|panic| {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            Err(VerdictError::Panicked {
                origin: origin.to_string(),
                what,
            })
        })
    })
}

/// Resolve `source` and decide everything about it, on the analysis thread.
pub fn check(source: &Source<'_>, options: &Options) -> Result<Verdict, VerdictError> {
    on_analysis_thread(&source.origin(), || {
        let r = resolve(source)?;
        Verdict::of(&r.origin, &r.table, options)
    })
}
