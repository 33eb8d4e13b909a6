//! The processor of a designed kernel, and the processed method's table.
//!
//! **The processor's form.** `χ = S(z₁h)⋯S(z_kh) S(−z₁h)⋯S(−z_kh)`, steps of
//! the kernel's own basic method, so `Σ` of its steps is zero and `χ` costs
//! nothing per step (it is applied at output only); Blanes, Casas & Murua
//! (2006) use this form. Its `k` coefficients are the unknowns.
//!
//! **Its conditions.** The kernel's elimination ([`crate::effective`]) at
//! the polished kernel gives the conjugator `Z` the processor must match:
//! `log χ = −Z` on the Lyndon words of weights `2..p − 1` makes `χ K χ⁻¹`
//! of order `p` (the kernel's conditions do the rest), and the same at
//! weight `p` is the objective: it is what leaves only the unremovable part
//! of the weight-`p + 1` error. The form ties coefficients of `log χ`
//! together, so these conditions are dependent, and a subset independent at
//! a random point can hold on a branch where the rest fail (measured at
//! effective order 8: two of eight tables refused). The pipeline therefore
//! runs Levenberg–Marquardt on all of them ([`crate::solve`]), ranks the
//! processors by the objective afterwards, and polishes a square subset
//! independent at the processor found ([`independent`], [`crate::polish`]);
//! the table's claim then decides whether every condition holds.
//!
//! **The table.** The processed method is written as `symlab check` reads
//! one: the kernel inline (`compose`), the processor as its drift–kick
//! sequence (`corrector_drift`, `corrector_kick`), with the claim
//! `order = p (residual < 1e-40)` about the effective method `χ K χ⁻¹`,
//! which tableau decides exactly on the printed decimals
//! ([`tableau::near_integrable::check_processed_claim`]): every Lie term up
//! to degree `p` in the letters `A`, `B` is below the bound.

use std::collections::HashMap;

use num_rational::BigRational;
use num_traits::{One, Zero};

use crate::conditions::{Condition, Factor, System, log_coefficient, product};
use crate::effective::{Series, eliminate};
use crate::emit::quote;
use crate::family::{Family, FamilyError, Form};
use crate::poly::Poly;
use tableau::certificate::{is_lyndon, word_label, words_of_weight};

/// The bound the emitted claim states: the printed values carry 50
/// decimals, so every Lie term up to the order is far below it.
pub const RESIDUAL_BOUND: &str = "1e-40";

fn error(file: &str, field: Option<&str>, message: String) -> FamilyError {
    FamilyError {
        file: file.to_string(),
        field: field.map(str::to_string),
        message,
    }
}

/// The log series of a composition of steps `γ` (constant or not), every
/// word up to weight `top`.
fn log_of_steps(gamma: &[Poly], top: usize, nvars: usize) -> Series {
    let factors: Vec<Factor<'_>> = gamma.iter().map(Factor::Step).collect();
    let prod = product(Form::Composition, &factors, top, nvars, &|_| true);
    let mut out: Series = HashMap::new();
    for n in 1..=top {
        for w in words_of_weight(true, n) {
            let c = log_coefficient(&prod, &w, nvars);
            if !c.is_zero() {
                out.insert(w, c);
            }
        }
    }
    out
}

/// The kernel's steps at the printed unknowns, exactly.
pub fn kernel_steps(kernel: &System, x: &[BigRational]) -> Vec<BigRational> {
    kernel.gamma.iter().map(|g| g.eval_rational(x)).collect()
}

/// The processor's system for the kernel `kernel` at the unknowns `x`.
pub fn processor_system(
    family: &Family,
    file: &str,
    kernel: &System,
    x: &[BigRational],
) -> Result<System, FamilyError> {
    let p = family.order;
    let steps: Vec<Poly> = kernel_steps(kernel, x)
        .into_iter()
        .map(|g| Poly::constant(0, g))
        .collect();
    let log_k = log_of_steps(&steps, p + 1, 0);
    let elim = eliminate(&log_k, p, 0, true).map_err(|e| error(file, None, e.to_string()))?;
    let z = elim.conjugator;
    let k = family.processor_stages / 2;
    let names: Vec<String> = (1..=k).map(|i| format!("z{i}")).collect();
    let mut gamma: Vec<Poly> = (0..k).map(|i| Poly::var(k, i)).collect();
    gamma.extend((0..k).map(|i| Poly::var(k, i).scale(&-BigRational::one())));
    let log_chi = log_of_steps(&gamma, p, k);
    let mut conditions = Vec::new();
    let mut error_terms = Vec::new();
    for n in 2..=p {
        for w in words_of_weight(true, n)
            .into_iter()
            .filter(|w| is_lyndon(w))
        {
            let target = z
                .get(&w)
                .and_then(Poly::as_constant)
                .unwrap_or_else(BigRational::zero);
            let poly = log_chi
                .get(&w)
                .cloned()
                .unwrap_or_else(|| Poly::zero(k))
                .add(&Poly::constant(k, target));
            if poly.is_zero() {
                continue;
            }
            let label = word_label(true, &w);
            if n < p && poly.as_constant().is_some() {
                return Err(error(
                    file,
                    Some("processor_stages"),
                    format!(
                        "a processor S(z₁h)⋯S(z_kh) S(−z₁h)⋯S(−z_kh) cannot match the kernel's conjugator on {label} (weight {n}): its coefficient there is a constant"
                    ),
                ));
            }
            let c = Condition {
                word: label,
                degree: n,
                poly,
            };
            if n < p {
                conditions.push(c);
            } else {
                error_terms.push(c);
            }
        }
    }
    // (The form ties some coefficients of log χ together, so these
    // conditions are dependent; `independent` picks a square subset at a
    // solution for the polish.)
    let mut rng = crate::solve::SplitMix64::new(family.seed);
    let generic: Vec<f64> = (0..k).map(|_| rng.symmetric(1.0)).collect();
    if conditions.len() > k && independent(&conditions, k, &generic).len() == k {
        return Err(error(
            file,
            Some("processor_stages"),
            format!(
                "the processor must meet {} conditions ({}) with {k} unknowns: give it more stages",
                conditions.len(),
                conditions
                    .iter()
                    .map(|c| c.word.clone())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ));
    }
    Ok(System {
        form: Form::Composition,
        order: p,
        generalised: Vec::new(),
        stages: family.processor_stages,
        parameters: names
            .iter()
            .cloned()
            .zip((0..k).map(|i| Poly::var(k, i)))
            .collect(),
        names,
        drift: Vec::new(),
        kick: Vec::new(),
        gamma,
        conditions,
        error_terms,
        rkn: false,
    })
}

/// The indices of conditions whose gradients are independent at `x` (pivot
/// rows of the Jacobian): where the form ties coefficients together, the
/// others follow from these near `x`.
pub fn independent(conditions: &[Condition], k: usize, x: &[f64]) -> Vec<usize> {
    // Rows: unknowns; columns: conditions (the transpose of the Jacobian).
    let jt: Vec<Vec<f64>> = (0..k)
        .map(|j| {
            conditions
                .iter()
                .map(|c| c.poly.derivative(j).compile().eval(x))
                .collect()
        })
        .collect();
    let mut keep = crate::linalg::pivot_columns(&jt, 1e-9);
    keep.sort_unstable();
    keep
}

/// The processor's drift–kick sequence: the steps `S(γ) = D(γ/2) K(γ)
/// D(γ/2)` with neighbouring drifts merged, as tableau turns a composition
/// into a sequence; the entries as text in the unknowns' names.
fn processor_sequence(k: usize) -> (Vec<String>, Vec<String>) {
    // Step i: (negated, the unknown's name).
    let step = |i: usize| -> (bool, String) {
        if i < k {
            (false, format!("z{}", i + 1))
        } else {
            (true, format!("z{}", i - k + 1))
        }
    };
    let signed = |(neg, name): (bool, String)| {
        if neg { format!("-{name}") } else { name }
    };
    let m = 2 * k;
    let mut drift = Vec::with_capacity(m + 1);
    for j in 0..=m {
        let text = if j == 0 {
            format!("{}/2", signed(step(0)))
        } else if j == m {
            format!("{}/2", signed(step(m - 1)))
        } else {
            let (neg, name) = step(j);
            let op = if neg { "-" } else { "+" };
            format!("({} {op} {name})/2", signed(step(j - 1)))
        };
        drift.push(text);
    }
    let kick = (0..m).map(|i| signed(step(i))).collect();
    (drift, kick)
}

/// What the processed table says about its kernel's proof.
pub struct KernelProof<'a> {
    /// The Krawczyk radius around the printed determined unknowns.
    pub radius: &'a BigRational,
    pub determined: Vec<&'a str>,
}

/// The processed method's table file.
#[allow(clippy::too_many_arguments)]
pub fn table_text(
    family: &Family,
    family_file: &str,
    kernel: &System,
    x: &[BigRational],
    processor: &System,
    z: &[BigRational],
    rank: usize,
    effective_error: f64,
    proof: &KernelProof<'_>,
) -> String {
    use crate::polish::{DIGITS, decimal_text};
    let mut out = String::new();
    out.push_str(&format!(
        "# Designed by `symlab design {family_file}` (family \"{}\", seed {}): kernel {rank} of its\n",
        family.name, family.seed
    ));
    out.push_str(&format!(
        "# search, ranked by the effective error E_f = s·(Σ e²)^(1/(2p)) = {effective_error:.6e} over the\n# part of weight {} that no processor removes.\n",
        family.order + 1
    ));
    out.push_str(&format!(
        "# The kernel: an exact solution of its {} effective-order conditions lies within {:.3e}\n# (max norm) of the printed {} (Krawczyk, exact rational interval arithmetic).\n",
        kernel.conditions.len(),
        crate::poly::to_f64(proof.radius),
        proof.determined.join(", ")
    ));
    out.push_str(&format!(
        "# The processor χ = S(z₁h)⋯S(z_{k}h) S(−z₁h)⋯S(−z_{k}h) (applied at output, χ⁻¹ once on entry)\n# meets its {} conditions to the printed digits; the claim below is about χ K χ⁻¹ and\n# `symlab check` decides it on the printed decimals.\n",
        processor.conditions.len(),
        k = processor.names.len()
    ));
    out.push_str(&format!(
        "name = {}\n",
        quote(&format!("{} #{rank}", family.name))
    ));
    out.push_str(&format!(
        "source = {}\n",
        quote(&format!(
            "symlab design {family_file} (seed {}){}",
            family.seed,
            family
                .source
                .as_ref()
                .map(|s| format!("; the family as in {s}"))
                .unwrap_or_default()
        ))
    ));
    out.push_str(&format!(
        "claims = [\"symplectic\", \"explicit\", \"order = {} (residual < {RESIDUAL_BOUND})\"]\n",
        family.order
    ));
    let names = &kernel.names;
    for (name, value) in names.iter().zip(x) {
        out.push_str(&format!(
            "let.{name} = \"{}\"\n",
            decimal_text(value, DIGITS)
        ));
    }
    for (name, value) in processor.names.iter().zip(z) {
        out.push_str(&format!(
            "let.{name} = \"{}\"\n",
            decimal_text(value, DIGITS)
        ));
    }
    let compose: Vec<String> = kernel
        .gamma
        .iter()
        .map(|g| quote(&g.to_text(names)))
        .collect();
    out.push_str(&format!("compose = [{}]\n", compose.join(", ")));
    let (drift, kick) = processor_sequence(processor.names.len());
    let q = |v: Vec<String>| v.iter().map(|s| quote(s)).collect::<Vec<_>>().join(", ");
    out.push_str(&format!("corrector_drift = [{}]\n", q(drift)));
    out.push_str(&format!("corrector_kick = [{}]\n", q(kick)));
    out
}

/// Decide every claim of a processed table's text with tableau, as `symlab
/// check` does: `Ok` with the claims, or the first refusal.
pub fn check_text(origin: &str, text: &str) -> Result<Vec<String>, String> {
    let file = tableau::file::parse_table_file(origin, text).map_err(|e| e.to_string())?;
    let corrector = file
        .corrector_table()
        .ok_or_else(|| format!("{origin}: no corrector"))?;
    let mut held = Vec::new();
    for claim in &file.claims {
        if let Some(result) =
            tableau::near_integrable::check_processed_claim(&file.table, &corrector, claim)
        {
            result.map_err(|e| format!("{origin}: claim `{claim}` refused: {e}"))?;
            held.push(claim.to_string());
        }
    }
    Ok(held)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_processor_sequence_merges_neighbouring_drifts() {
        let (d, k) = processor_sequence(2);
        assert_eq!(
            d,
            [
                "z1/2",
                "(z1 + z2)/2",
                "(z2 - z1)/2",
                "(-z1 - z2)/2",
                "-z2/2"
            ]
        );
        assert_eq!(k, ["z1", "z2", "-z1", "-z2"]);
    }
}
