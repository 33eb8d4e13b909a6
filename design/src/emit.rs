//! The emitted table file: a drift–kick sequence or composition in the
//! format `symlab check` reads (`tableau::file`), with the unknowns bound in
//! `let` (50 decimals for a determined unknown, its exact radicals when it
//! has them), every coefficient written as the family's exact affine
//! expression in them (so consistency and symmetry hold exactly), the
//! claims, and the certificate: `order = p (certified)` with
//! `certificate = { unknowns = [...], radius = "1e-46" }`, which `symlab
//! check` re-proves itself (`tableau::certificate`), and the same in a
//! comment line that the family-aware verifier (module `verify`) reads
//! back:
//!
//! ```text
//! # design-certificate: determined = a1 a2; radius = 1/10000000000…
//! ```

use num_rational::BigRational;

use crate::certify::Certificate;
use crate::conditions::System;
use crate::exact::Exact;
use crate::family::{Family, Form};
use crate::polish::{DIGITS, FREE_DIGITS, decimal_text};
use crate::poly::Poly;

/// The comment line's key.
pub const CERTIFICATE_KEY: &str = "# design-certificate:";

/// What the emitted table says about its coefficients.
pub enum Proof<'a> {
    /// The one unknown is exact, in radicals.
    Exact(&'a Exact),
    /// A Krawczyk certificate around the printed decimals.
    Certified {
        certificate: &'a Certificate,
        determined: &'a [usize],
    },
}

/// `4`, or `(6, 2)` for a generalised order.
fn claimed_order(system: &System) -> String {
    if system.generalised.is_empty() {
        system.order.to_string()
    } else {
        let items: Vec<String> = system.generalised.iter().map(usize::to_string).collect();
        format!("({})", items.join(", "))
    }
}

/// A TOML basic string.
pub(crate) fn quote(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

/// The coefficients of the method as text in the unknowns' names.
fn entries(polys: &[Poly], names: &[String]) -> Vec<String> {
    polys.iter().map(|p| quote(&p.to_text(names))).collect()
}

/// The table file's text.
pub fn table_text(
    family: &Family,
    family_file: &str,
    system: &System,
    x: &[BigRational],
    rank: usize,
    effective_error: f64,
    proof: &Proof<'_>,
) -> String {
    let mut out = String::new();
    out.push_str(&format!(
        "# Designed by `symlab design {family_file}` (family \"{}\", seed {}): solution {rank} of its\n",
        family.name, family.seed
    ));
    out.push_str(&format!(
        "# search, ranked by the effective error E_f = s·(Σ e²)^(1/(2p)) = {effective_error:.6e} over the\n# {} error terms of degree {}.\n",
        system.error_terms.len(),
        system.order + 1
    ));
    let names = &system.names;
    let mut certificate_line = None;
    let mut return_rkn = false;
    let claims = match proof {
        Proof::Exact(e) => {
            out.push_str(&format!(
                "# Exact: {} = {} (the real root of {} = 0 near the solver's value), in radicals below;\n# `symlab check` decides every claim exactly.\n",
                names[0], e.root, e.polynomial
            ));
            format!("\"order = {}\"", claimed_order(system))
        }
        Proof::Certified {
            certificate,
            determined,
        } => {
            let det: Vec<&str> = determined.iter().map(|&i| names[i].as_str()).collect();
            let free: Vec<&str> = (0..names.len())
                .filter(|i| !determined.contains(i))
                .map(|i| names[i].as_str())
                .collect();
            out.push_str(&format!(
                "# Certified (Krawczyk, exact rational interval arithmetic): an exact solution of the order-{} conditions\n# lies within {:.3e} (max norm) of the printed {}{}; on that box the\n# error term {} lies in [{:.6e}, {:.6e}], so the order is exactly {}.\n",
                system.order,
                crate::poly::to_f64(&certificate.radius),
                det.join(", "),
                if free.is_empty() {
                    String::new()
                } else {
                    format!(" (with {} exact as printed)", free.join(", "))
                },
                certificate.next_order.as_ref().map_or("?", |t| t.0.as_str()),
                certificate.next_order.as_ref().map_or(0.0, |t| t.1),
                certificate.next_order.as_ref().map_or(0.0, |t| t.2),
                system.order
            ));
            out.push_str(&format!(
                "{CERTIFICATE_KEY} determined = {}; radius = {}\n",
                det.join(" "),
                certificate.radius
            ));
            if system.rkn && system.order > 4 {
                // The certificate is for the RKN conditions, which tableau's
                // certificate (classical Lie conditions) does not build: the
                // claims are residual bounds on the printed digits, which
                // `symlab check` decides exactly (the catalogue's form).
                return_rkn = true;
            }
            // The claim `symlab check` re-proves from the certificate (the
            // Krawczyk test, run anew on the file's own coefficients).
            certificate_line = Some(format!(
                "certificate = {{ unknowns = [{}], radius = {} }}\n",
                det.iter().map(|d| quote(d)).collect::<Vec<_>>().join(", "),
                quote(&tableau::certificate::radius_text(&certificate.radius))
            ));
            format!("\"order = {} (certified)\"", claimed_order(system))
        }
    };
    let (claims, certificate_line) = if return_rkn {
        (
            format!(
                "\"order = 4 (residual < 1e-40)\", \"order_rkn = {} (residual < 1e-40)\"",
                system.order
            ),
            None,
        )
    } else {
        (claims, certificate_line)
    };
    out.push_str(&format!("name = {}\n", quote(&family.name)));
    out.push_str(&format!(
        "source = {}\n",
        quote(&format!(
            "symlab design {family_file}{}",
            family
                .source
                .as_ref()
                .map_or(String::new(), |s| format!(" (compare: {s})"))
        ))
    ));
    out.push_str(&format!(
        "claims = [\"symplectic\", \"symmetric\", {claims}]\n"
    ));
    if let Some(line) = certificate_line {
        out.push_str(&line);
    }
    for (i, name) in names.iter().enumerate() {
        let value = match proof {
            Proof::Exact(e) => e
                .radicals
                .clone()
                .unwrap_or_else(|| decimal_text(&x[i], DIGITS)),
            Proof::Certified { determined, .. } => {
                let digits = if determined.contains(&i) {
                    DIGITS
                } else {
                    FREE_DIGITS
                };
                decimal_text(&x[i], digits)
            }
        };
        out.push_str(&format!("let.{name} = {}\n", quote(&value)));
    }
    out.push_str(&method_lines(system, names));
    out
}

/// The method's own lines of a table file: `compose = […]`, or `drift = […]`
/// and `kick = […]`, the entries as text in `names`.
pub(crate) fn method_lines(system: &System, names: &[String]) -> String {
    match system.form {
        Form::Composition => format!("compose = [{}]\n", entries(&system.gamma, names).join(", ")),
        Form::Aba => format!(
            "drift = [{}]\nkick = [{}]\n",
            entries(&system.drift, names).join(", "),
            entries(&system.kick, names).join(", ")
        ),
        Form::Bab => {
            // The format starts equal-length sequences with a drift: a
            // leading zero drift.
            let mut drift = vec![quote("0")];
            drift.extend(entries(&system.drift, names));
            format!(
                "drift = [{}]\nkick = [{}]\n",
                drift.join(", "),
                entries(&system.kick, names).join(", ")
            )
        }
    }
}
