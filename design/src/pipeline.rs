//! One design run: family → conditions → search → polish → exact value or
//! certificate → table files and a report. The library prints nothing; the
//! caller gets the progress through a callback and writes the files with
//! [`Outcome::write`].

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use num_rational::BigRational;

use crate::certify::{Certificate, Refusal, certify};
use crate::conditions::{System, system};
use crate::emit::{Proof, table_text};
use crate::exact::{Exact, exact_value};
use crate::family::{Family, FamilyError, stem};
use crate::polish::{DIGITS, PolishError, Polished, decimal_text, polish};
use crate::poly::to_f64;
use crate::processor::{
    KernelProof, check_text, independent, processor_system, table_text as processor_table_text,
};
use crate::solve::{Progress, Search, Solution, search};
use crate::stability::{Threshold, ThresholdError, flows_of, threshold};

/// The most solutions polished, certified and emitted (the best by the
/// objective).
pub const MAX_EMITTED: usize = 8;

/// The starts of a processor's search (at most the family's).
pub const PROCESSOR_STARTS: usize = 32;

/// One solution carried through to its table.
#[derive(Clone, Debug)]
pub struct Designed {
    pub solution: Solution,
    pub polished: Result<Polished, PolishError>,
    pub exact: Option<Exact>,
    /// `None` when the value is exact (no certificate needed) or the polish
    /// failed.
    pub certificate: Option<Result<Certificate, Refusal>>,
    /// The table file's name and text, when the solution was proven.
    pub table: Option<(String, String)>,
    /// The linear stability threshold `x* = hω` of the emitted table on the
    /// harmonic oscillator ([`crate::stability`]); `None` without a table.
    pub stability: Option<Result<Threshold, ThresholdError>>,
    /// For a processed kernel (`processed = true`): its processor, or why
    /// none was found; `None` for other families or an uncertified kernel.
    pub processor: Option<Result<ProcessorDesign, String>>,
}

/// A processed kernel's processor ([`crate::processor`]).
#[derive(Clone, Debug)]
pub struct ProcessorDesign {
    /// Its conditions and objective, in `z1, z2, …`.
    pub system: System,
    pub search: Search,
    /// The printed coefficients (50 decimals where determined).
    pub z: Vec<BigRational>,
    /// The claims tableau decided on the emitted table's text.
    pub claims: Vec<String>,
    /// Its objective: `Σ e²` of the image part of weight `p` it leaves
    /// (at the `f64` solution).
    pub objective: f64,
}

/// The processor for the kernel `x`, its table's text, and the claims
/// tableau decided on it.
fn process(
    family: &Family,
    family_file: &str,
    system: &System,
    kernel: &Polished,
    certificate: &Certificate,
    rank: usize,
    effective_error: f64,
) -> Result<(ProcessorDesign, String, String), String> {
    let (x, determined) = (&kernel.x, &kernel.determined);
    let psys = processor_system(family, family_file, system, x).map_err(|e| e.to_string())?;
    let mut pfamily = family.clone();
    pfamily.stages = family.processor_stages;
    // Any processor that meets the conditions gives the kernel's effective
    // order; the objective only trims the image part of the next weight, so
    // a few starts suffice.
    pfamily.starts = family.starts.min(PROCESSOR_STARTS);
    // The conditions are dependent (the form ties coefficients of log χ
    // together), so the search runs Levenberg–Marquardt on all of them
    // without the constrained minimisation, and the processors found are
    // ranked by the objective afterwards.
    let mut bare = psys.clone();
    bare.error_terms.clear();
    let found = search(&bare, &pfamily, &mut |_| {});
    let full = crate::solve::Compiled::new(&psys);
    let best = found
        .solutions
        .iter()
        .min_by(|a, b| full.objective(&a.x).total_cmp(&full.objective(&b.x)))
        .ok_or_else(|| {
            format!(
                "no processor found: none of {} starts met its {} conditions",
                found.starts_run,
                psys.conditions.len()
            )
        })?
        .clone();
    // The polish: a square subset, independent at the processor found; the
    // rest must then hold too, which the table's claim decides.
    let mut square = psys.clone();
    let keep = independent(&psys.conditions, psys.unknowns(), &best.x);
    square.conditions = keep.iter().map(|&i| psys.conditions[i].clone()).collect();
    let polished = polish(&square, &best).map_err(|e| format!("the processor's polish: {e}"))?;
    let name = format!("{}-{rank}.toml", stem(&family.name));
    let proof = KernelProof {
        radius: &certificate.radius,
        determined: determined
            .iter()
            .map(|&i| system.names[i].as_str())
            .collect(),
    };
    let text = processor_table_text(
        family,
        family_file,
        system,
        x,
        &psys,
        &polished.x,
        rank,
        effective_error,
        &proof,
    );
    let claims = check_text(&name, &text)?;
    Ok((
        ProcessorDesign {
            system: psys,
            search: found,
            z: polished.x,
            claims,
            objective: full.objective(&best.x),
        },
        name,
        text,
    ))
}

/// The bits to which [`Designed::stability`] encloses `x*²`.
pub const STABILITY_PRECISION: u32 = 64;

/// The stability threshold of a table's text, as `symlab check` reads it.
fn stability_of(name: &str, text: &str) -> Option<Result<Threshold, ThresholdError>> {
    let file = tableau::file::parse_table_file(name, text).ok()?;
    let flows = flows_of(&file.table)?;
    Some(threshold(&flows, STABILITY_PRECISION))
}

/// A whole run.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub family: Family,
    pub family_file: String,
    pub system: System,
    pub search: Search,
    pub designs: Vec<Designed>,
}

/// Run a family (read from `family_file`, which messages and the emitted
/// tables name).
pub fn design(
    family: &Family,
    family_file: &str,
    progress: &mut dyn FnMut(Progress),
) -> Result<Outcome, FamilyError> {
    let system = system(family, family_file)?;
    let found = search(&system, family, progress);
    let mut designs = Vec::new();
    for (rank, solution) in found.solutions.iter().take(MAX_EMITTED).enumerate() {
        let rank = rank + 1;
        let polished = polish(&system, solution);
        let exact = if family.processed {
            // A processed kernel is proven by its certificate and its
            // processed table's claims, decided by tableau.
            None
        } else {
            exact_value(&system, solution.x.first().copied().unwrap_or(0.0))
                .filter(|e| e.radicals.is_some())
        };
        let mut certificate = None;
        let mut table = None;
        let mut processor = None;
        if let (true, Ok(p)) = (family.processed, &polished) {
            let c = certify(&system, &p.x, &p.determined, DIGITS - 4);
            if let Ok(cert) = &c {
                let made = process(
                    family,
                    family_file,
                    &system,
                    p,
                    cert,
                    rank,
                    solution.effective_error,
                );
                processor = Some(made.map(|(design, name, text)| {
                    table = Some((name, text));
                    design
                }));
            }
            certificate = Some(c);
        } else if let Ok(p) = &polished {
            let name = format!("{}-{rank}.toml", stem(&family.name));
            match &exact {
                Some(e) => {
                    let text = table_text(
                        family,
                        family_file,
                        &system,
                        &p.x,
                        rank,
                        solution.effective_error,
                        &Proof::Exact(e),
                    );
                    table = Some((name, text));
                }
                None => {
                    let c = certify(&system, &p.x, &p.determined, DIGITS - 4);
                    if let Ok(cert) = &c {
                        let text = table_text(
                            family,
                            family_file,
                            &system,
                            &p.x,
                            rank,
                            solution.effective_error,
                            &Proof::Certified {
                                certificate: cert,
                                determined: &p.determined,
                            },
                        );
                        table = Some((name, text));
                    }
                    certificate = Some(c);
                }
            }
        }
        let stability = table
            .as_ref()
            .and_then(|(name, text)| stability_of(name, text));
        designs.push(Designed {
            solution: solution.clone(),
            polished,
            exact,
            certificate,
            table,
            stability,
            processor,
        });
    }
    Ok(Outcome {
        family: family.clone(),
        family_file: family_file.to_string(),
        system,
        search: found,
        designs,
    })
}

impl Designed {
    /// `x*/s`, the stability threshold per force evaluation (`stages` of
    /// the family); `None` without a table or a threshold.
    pub fn stability_per_stage(&self, stages: usize) -> Option<f64> {
        match &self.stability {
            Some(Ok(t)) => Some(t.x() / stages as f64),
            _ => None,
        }
    }
}

impl Outcome {
    /// The report, in Markdown.
    pub fn report(&self) -> String {
        let f = &self.family;
        let s = &self.system;
        let mut r = String::new();
        let _ = writeln!(r, "# Design: {}\n", f.name);
        let _ = writeln!(
            r,
            "Family `{}`: {} with {} stages, {}order {} imposed; seed {}, {} starts in [-{}, {}], cap {} s.\n",
            self.family_file,
            f.form.name(),
            f.stages,
            if f.generalised.is_empty() {
                ""
            } else {
                "generalised "
            },
            f.order_text(),
            f.seed,
            f.starts,
            f.range,
            f.range,
            f.max_seconds
        );
        let degree_text = if f.generalised.is_empty() {
            format!("of degree {}", s.order + 1)
        } else {
            "one degree beyond the claim in each power of ε".to_string()
        };
        let _ = writeln!(
            r,
            "Unknowns: {} ({}); conditions: {} ({}); error terms {}: {}.\n",
            s.unknowns(),
            s.names.join(", "),
            s.conditions.len(),
            s.conditions
                .iter()
                .map(|c| c.word.clone())
                .collect::<Vec<_>>()
                .join(", "),
            degree_text,
            s.error_terms.len()
        );
        let _ = writeln!(r, "Parameters in the unknowns:\n");
        for (name, p) in &s.parameters {
            let _ = writeln!(r, "- {name} = {}", p.to_text(&s.names));
        }
        let _ = writeln!(r, "\nConditions (each must vanish):\n");
        for c in &s.conditions {
            let text = c.poly.to_text(&s.names);
            let shown = if text.len() > 400 {
                format!(
                    "{}… ({} terms)",
                    &text[..text.char_indices().nth(400).map_or(text.len(), |(i, _)| i)],
                    c.poly.terms().count()
                )
            } else {
                text
            };
            let _ = writeln!(r, "- {} (h^{}): {shown}", c.word, c.degree);
        }
        let se = &self.search;
        let _ = writeln!(
            r,
            "\nSearch: {} starts run in {:.2} s{}, {} converged onto the conditions, {} distinct solutions.\n",
            se.starts_run,
            se.elapsed.as_secs_f64(),
            if se.capped {
                " (stopped by the time cap)"
            } else {
                ""
            },
            se.converged,
            se.solutions.len()
        );
        let measure = match (self.family.rkn, self.family.error_basis) {
            _ if self.family.processed && !self.family.generalised.is_empty() => {
                "the coordinates outside the image of ad Y₁ at one degree beyond the claim in each power of ε (what no processor removes once the terms with fewer ε are removed: least squares block by block, `design::effective::eliminate_near`)"
            }
            _ if self.family.processed => {
                "the coordinates outside the image of ad Y₁ (what no processor removes, orthogonally projected on the Lyndon-word coefficients)"
            }
            (true, _) => {
                "the coordinates in the Lyndon basis outside the ideal of [B,[B,[B,A]]] (RKN)"
            }
            (false, crate::ErrorBasis::Brackets) => "the coordinates in the Lyndon basis",
            (false, crate::ErrorBasis::Words) => "the Lyndon-word coefficients",
        };
        let _ = writeln!(
            r,
            "Effective error E_f = s·(Σ e²)^(1/(2p)), e {measure}{} in log Φ.\n",
            if self.family.processed && !self.family.generalised.is_empty() {
                ""
            } else {
                " of degree p + 1"
            }
        );
        let _ = writeln!(
            r,
            "x*/s: the linear stability threshold hω of the emitted table on the harmonic oscillator, per force evaluation (enclosed exactly, `design::stability`).\n"
        );
        if f.objective == crate::family::Objective::Stability {
            let _ = writeln!(
                r,
                "Objective \"stability\": from the best {} solutions of the error search, the free coefficients moved to a local maximum of x* on the conditions (a compass search, x* at the double coefficients); ranked by x*, largest first.\n",
                crate::solve::STABILITY_STARTS
            );
        }
        let _ = writeln!(
            r,
            "| rank | {} | Σ e² | E_f | x*/s | hits | proof | table |",
            s.names.join(" | ")
        );
        let _ = writeln!(r, "|{}", "---|".repeat(s.names.len() + 7));
        for (i, d) in self.designs.iter().enumerate() {
            let proof = match (&d.exact, &d.certificate, &d.polished) {
                (Some(e), _, _) => format!(
                    "exact: {} = {}",
                    s.names[0],
                    e.radicals.as_deref().unwrap_or(&e.root)
                ),
                (_, Some(Ok(c)), _) => format!("certified, radius {:.1e}", to_f64(&c.radius)),
                (_, Some(Err(e)), _) => format!("refused: {e}"),
                (_, None, Err(e)) => format!("polish failed: {e}"),
                _ => "—".into(),
            };
            let _ = writeln!(
                r,
                "| {} | {} | {:.6e} | {:.6} | {} | {} | {proof} | {} |",
                i + 1,
                d.solution
                    .x
                    .iter()
                    .map(|v| format!("{v:.16}"))
                    .collect::<Vec<_>>()
                    .join(" | "),
                d.solution.objective,
                d.solution.effective_error,
                d.stability_per_stage(f.stages)
                    .map_or("—".to_string(), |x| format!("{x:.6}")),
                d.solution.hits,
                d.table.as_ref().map_or("—", |t| t.0.as_str())
            );
        }
        if f.processed {
            let _ = writeln!(
                r,
                "\nProcessed kernels: the conditions are of effective order {} (of χ K χ⁻¹, `design::effective`). Each certified kernel gets a processor {} (`design::processor`; at most {} starts, the best by the image part of the first degree not imposed kept), and its table's claim is decided by `symlab check`'s verifier:\n",
                f.order_text(),
                crate::processor::processor_form(f.form, f.processor_stages),
                PROCESSOR_STARTS,
            );
            for (i, d) in self.designs.iter().enumerate() {
                match &d.processor {
                    None => {
                        let _ = writeln!(
                            r,
                            "- kernel {}: no processor (the kernel is not certified)",
                            i + 1
                        );
                    }
                    Some(Err(e)) => {
                        let _ = writeln!(r, "- kernel {}: no processor: {e}", i + 1);
                    }
                    Some(Ok(pd)) => {
                        let _ = writeln!(
                            r,
                            "- kernel {}: processor conditions {} ({}); {} starts, {} distinct processors, the best's image part Σ e² = {:.3e}; claims held: {}; ({}) = ({})",
                            i + 1,
                            pd.system.conditions.len(),
                            pd.system
                                .conditions
                                .iter()
                                .map(|c| c.word.clone())
                                .collect::<Vec<_>>()
                                .join(", "),
                            pd.search.starts_run,
                            pd.search.solutions.len(),
                            pd.objective,
                            pd.claims.join("; "),
                            pd.system.names.join(", "),
                            pd.z.iter()
                                .map(|z| format!("{:.16}", to_f64(z)))
                                .collect::<Vec<_>>()
                                .join(", ")
                        );
                    }
                }
            }
        }
        for (i, d) in self.designs.iter().enumerate() {
            if let Ok(p) = &d.polished {
                let _ = writeln!(
                    r,
                    "\nSolution {} in high precision ({} Newton steps):\n",
                    i + 1,
                    p.steps
                );
                for (k, name) in s.names.iter().enumerate() {
                    let digits = if p.determined.contains(&k) {
                        DIGITS
                    } else {
                        crate::polish::FREE_DIGITS
                    };
                    let _ = writeln!(r, "- {name} = {}", decimal_text(&p.x[k], digits));
                }
                if let Some(e) = &d.exact {
                    let _ = writeln!(r, "- exact: {} = {}", s.names[0], e.root);
                }
            }
        }
        r
    }

    /// Write every emitted table and `report.md` into `dir` (created); the
    /// paths written.
    pub fn write(&self, dir: &Path) -> std::io::Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir)?;
        let mut out = Vec::new();
        for d in &self.designs {
            if let Some((name, text)) = &d.table {
                let p = dir.join(name);
                std::fs::write(&p, text)?;
                out.push(p);
            }
        }
        let p = dir.join("report.md");
        std::fs::write(&p, self.report())?;
        out.push(p);
        Ok(out)
    }
}
