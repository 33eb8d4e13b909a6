//! The JSON object of a verdict (its fields are listed in the module
//! documentation of [`super`]).

use serde_json::{Value, json};

use super::{Analysed, ClaimVerdict, Verdict, near};
use crate::algebraic::file::{AlgAnalysis, AlgFile};
use crate::algebraic::generated::Generated;
use crate::analysis::{Analysis, Form};
use crate::file::TableFile;

pub(super) fn verdict(v: &Verdict) -> Value {
    let mut out = match &v.analysed {
        Analysed::Classic {
            file,
            analysis,
            near,
            certificate,
        } => {
            let mut out = classic(file, analysis);
            match certificate.as_deref() {
                Some(Ok(p)) => {
                    out["certificate"] = json!({
                        "order": p.order,
                        "generalised": (!p.generalised.is_empty()).then_some(&p.generalised),
                        "radius": crate::certificate::radius_text(&p.radius),
                        "unknowns": p.unknowns,
                        "conditions": p.conditions,
                        "contraction": p.contraction,
                        "offset": p.offset,
                        "next_order": p.next_order.as_ref().map(|(w, lo, hi)| json!({"word": w, "lo": lo, "hi": hi})),
                        "summary": p.summary(),
                    });
                }
                Some(Err(e)) => out["certificate"] = json!({ "refused": e }),
                None => {}
            }
            if let Some(n) = near {
                out["near_integrable"] = near::json(n);
            }
            if let Some(chi) = &file.corrector {
                out["processed"] = json!({
                    "kernel": file.kernel,
                    "corrector_drift": chi.drift.iter().map(|x| x.to_string()).collect::<Vec<_>>(),
                    "corrector_kick": chi.kick.iter().map(|x| x.to_string()).collect::<Vec<_>>(),
                    "effective_flows": near::effective_flows(file),
                });
            }
            out
        }
        Analysed::Generated(g) => generated(g),
        Analysed::Algebraic { file, analysis } => algebraic(file, analysis),
    };
    out["origin"] = v.origin.clone().into();
    out["claims"] = claims(&v.claims);
    out["report"] = v.to_string().into();
    out
}

fn claims(claims: &[ClaimVerdict]) -> Value {
    claims
        .iter()
        .map(|c| {
            json!({
                "claim": c.claim,
                "holds": c.verdict.is_ok(),
                "reason": c.verdict.as_ref().err(),
            })
        })
        .collect()
}

/// The fields of design.md, field for field, with `w_nonzero`'s values
/// exact and as doubles.
fn classic(tf: &TableFile, a: &Analysis) -> Value {
    let order_report = a.order.as_ref().unwrap_or(&a.order_separable);
    json!({
        "name": tf.name,
        "kind": a.kind(),
        "stages": a.stages,
        "class": a.class.name(),
        "row_sums_ok": a.row_sum_mismatch.is_empty(),
        "symplectic": a.symplectic,
        "symplectic_separable": a.symplectic_separable,
        "order": a.order.as_ref().map(|o| o.order),
        "order_separable": a.order_separable.order,
        "order_limit": order_report.limit,
        // A sequence with gradient kicks has no Nyström trees: its order on
        // RKN systems is not decided (null), only bounded below.
        "order_rkn": (a.form != Form::GradientDriftKick).then_some(a.order_rkn.order),
        "symmetric": a.symmetric,
        "stability_function": a.stability.as_ref().map(|r| r.to_text()),
        "stability_not_computed": a.stability_not_computed.as_ref().map(|e| e.to_string()),
        "w_nonzero": a.w_nonzero.iter().map(|e| json!({
            "i": e.i,
            "j": e.j,
            "value": e.value.to_string(),
            "value_f64": e.value.to_f64(),
        })).collect::<Vec<_>>(),
    })
}

/// The fields of design.md for a generated table, plus `generator`,
/// `node_polynomial`, `order_proof`, `order_upper`, `a_stable`,
/// `max_w_rounded` and the timings.
fn generated(g: &Generated) -> Value {
    json!({
        "name": g.name,
        "generator": g.generator.expression(),
        "node_polynomial": g.node_polynomial.to_text("x"),
        "kind": g.kind,
        "stages": g.stages,
        "class": if g.stages == 1 { "sdirk" } else { "implicit" },
        "row_sums_ok": g.row_sums_ok,
        "symplectic": g.symplectic,
        "symplectic_separable": g.symplectic,
        "order": if g.kind == "prk" && g.tree_order.is_none() {
            Value::Null
        } else {
            json!(g.proven_order())
        },
        "order_upper": g.order.upper,
        "order_proof": g.order.text,
        "order_proof_p": g.order_p.as_ref().map(|o| o.text.clone()),
        "tree_order": g.tree_order.as_ref().map(|t| t.order),
        "tree_order_limit": g.tree_order.as_ref().map(|t| t.limit),
        "symmetric": g.symmetric,
        "stability_function": g.stability.as_ref().map(|r| r.to_text()),
        "a_stable": g.a_stable,
        "r_infinity": g.r_infinity.as_ref().map(|r| r.to_string()),
        "max_w_rounded": g.max_w_rounded,
        "max_w_nearest": g.max_w_nearest,
        "verify_ms": g.verify_time.as_secs_f64() * 1e3,
        "round_ms": g.round_time.as_secs_f64() * 1e3,
    })
}

/// A table with `root(...)` entries.
fn algebraic(f: &AlgFile, an: &AlgAnalysis) -> Value {
    // W is symmetric (Wᵢⱼ = bᵢaᵢⱼ + bⱼaⱼᵢ − bᵢbⱼ): the analysis decides
    // i ≤ j and both (i, j) and (j, i) are listed, as for other tables.
    let w: Vec<Value> = an
        .w
        .iter()
        .filter(|e| e.zero != Some(true))
        .flat_map(|e| {
            let one =
                |i: usize, j: usize| json!({"i": i, "j": j, "zero": e.zero, "value_f64": e.value});
            if e.i == e.j || an.pair {
                vec![one(e.i, e.j)]
            } else {
                vec![one(e.i, e.j), one(e.j, e.i)]
            }
        })
        .collect();
    let mut v = json!({
        "name": f.name,
        "kind": if an.pair { "prk" } else { "rk" },
        "stages": an.stages,
        "entries": "algebraic",
        "roots": f.field.names,
        "row_sums_ok": an.row_sums_ok,
        "symplectic": an.symplectic,
        "symplectic_separable": an.symplectic_separable,
        "w_nonzero": w,
        "b_levels": an.b_levels,
        "refusals": an.refusals,
    });
    if an.pair {
        v["b_hat_levels"] = json!(an.b_hat_levels);
    }
    v
}
