//! The order conditions of a family as exact polynomials in its unknowns.
//!
//! **Where they come from.** The same Lie-word theory tableau decides orders
//! with: a drift–kick sequence `exp(a₁A) exp(b₁B) ⋯` has
//! `log Φ = A + B + Σ` Lie terms, a term of degree `n` being of size `hⁿ`
//! (see `tableau::near_integrable`); a composition of a symmetric
//! second-order method `exp(γY₁ + γ³Y₃ + γ⁵Y₅ + …)` has
//! `log Φ = Y₁ + Σ` Lie terms in the free algebra on `Y₁, Y₃, …`, `Y_k` of
//! weight `k` (see `tableau::order::composition_order`). The product of
//! exponentials is formed in the free associative algebra truncated at
//! weight `p + 1`, with coefficients that are polynomials in the unknowns;
//! its logarithm is taken word by word; a Lie element vanishes exactly when
//! its coefficients on the Lyndon words do, so the conditions are those
//! coefficients (minus `1` for the letters of weight one).
//!
//! **Which conditions.** The families are palindromic, so `log Φ` is odd in
//! `h` and every even-degree Lyndon coefficient is identically zero: those
//! polynomials are computed and dropped when they are exactly zero, never
//! assumed. The consistency conditions (`Σ a = Σ b = 1`, `Σ γ = 1`) are
//! linear: they are solved exactly for the middle coefficient (the
//! literature's `a₃ = 1/2 − a₁ − a₂`) before anything else, and checked to
//! hold identically afterwards. What remains are the odd-degree Lyndon
//! coefficients of degree `3..=p`: coordinates of the Lie element, so
//! independent as functionals on the free Lie algebra (a family may still
//! make them dependent; the solver checks the Jacobian's rank at each
//! solution). The objective's terms are the Lyndon coefficients of degree
//! `p + 1`, the first order not imposed, or (`error_basis = "brackets"`,
//! `rkn = true`) the coordinates in the Lyndon basis, modulo the RKN ideal
//! for `rkn` ([`lyndon_basis_terms`]), which also gives the RKN conditions of
//! degree ≥ 5.

use std::collections::HashMap;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

use crate::family::{ErrorBasis, Family, FamilyError, Form};
use crate::poly::Poly;
use tableau::certificate::{factorial, is_lyndon, word_label, word_weight, words_of_weight};

/// One condition (or error term): the Lyndon word, its degree, the
/// polynomial that must vanish.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Condition {
    /// The Lyndon word, `AAB` or `Y₁Y₁Y₃`.
    pub word: String,
    /// The power of `h`.
    pub degree: usize,
    /// Coefficient minus target, in the unknowns.
    pub poly: Poly,
}

/// A family's unknowns, coefficients and conditions.
#[derive(Clone, Debug)]
pub struct System {
    pub form: Form,
    pub order: usize,
    /// The generalised order imposed (empty: the classical `order`).
    pub generalised: Vec<usize>,
    pub stages: usize,
    /// The unknowns' names (a subset of the family's parameters).
    pub names: Vec<String>,
    /// Every parameter of the family, in the unknowns (affine).
    pub parameters: Vec<(String, Poly)>,
    /// The drifts in the order applied (empty for a composition), affine in
    /// the unknowns.
    pub drift: Vec<Poly>,
    pub kick: Vec<Poly>,
    /// The step sizes of a composition.
    pub gamma: Vec<Poly>,
    /// The conditions imposed (degrees `2..=p`, not identically zero).
    pub conditions: Vec<Condition>,
    /// The error terms of degree `p + 1` (the objective's).
    pub error_terms: Vec<Condition>,
    /// Runge–Kutta–Nyström conditions (the family's `rkn`): from degree 5 on,
    /// the conditions are taken modulo the ideal of `[B,[B,[B,A]]]`.
    pub rkn: bool,
}

impl System {
    /// The number of unknowns.
    pub fn unknowns(&self) -> usize {
        self.names.len()
    }
}

/// Letters: `A = 0`, `B = 1` for drift–kick sequences; `Y₁ = 0`, `Y₃ = 1`,
/// … for compositions.
pub(crate) type Word = Vec<u8>;

/// The words' letters, weights and labels are tableau's (the certificate
/// builds the same conditions); a composition's letters are `Y₁, Y₃, …`.
fn comp(form: Form) -> bool {
    matches!(form, Form::Composition)
}

/// One factor of the product: `exp(x·L)` for a drift or kick, or
/// `exp(γY₁ + γ³Y₃ + …)` for a step of the base method.
pub(crate) enum Factor<'a> {
    Letter(u8, &'a Poly),
    Step(&'a Poly),
}

/// The factors of a method of the form `form`, in the order applied: its
/// steps (a composition), or its drifts and kicks interleaved, starting
/// with a drift (`ABA`) or a kick (`BAB`).
pub(crate) fn factors<'a>(
    form: Form,
    drift: &'a [Poly],
    kick: &'a [Poly],
    gamma: &'a [Poly],
) -> Vec<Factor<'a>> {
    let interleave = |first: &'a [Poly], fl: u8, second: &'a [Poly], sl: u8| {
        let mut f = Vec::new();
        for (i, x) in first.iter().enumerate() {
            f.push(Factor::Letter(fl, x));
            if let Some(y) = second.get(i) {
                f.push(Factor::Letter(sl, y));
            }
        }
        f
    };
    match form {
        Form::Composition => gamma.iter().map(Factor::Step).collect(),
        Form::Aba => interleave(drift, 0, kick, 1),
        Form::Bab => interleave(kick, 1, drift, 0),
    }
}

/// The coefficients of every word of weight `≤ top` in the product of the
/// factors' exponentials, with polynomial coefficients.
pub(crate) fn product(
    form: Form,
    factors: &[Factor<'_>],
    top: usize,
    nvars: usize,
    keep: &dyn Fn(&[u8]) -> bool,
) -> HashMap<Word, Poly> {
    let mut words: Vec<Word> = vec![Vec::new()];
    for n in 1..=top {
        words.extend(
            words_of_weight(comp(form), n)
                .into_iter()
                .filter(|w| keep(w)),
        );
    }
    let one = Poly::constant(nvars, BigRational::one());
    let mut p: HashMap<Word, Poly> = words
        .iter()
        .map(|w| {
            (
                w.clone(),
                if w.is_empty() {
                    one.clone()
                } else {
                    Poly::zero(nvars)
                },
            )
        })
        .collect();
    let max_len = words.iter().map(Vec::len).max().unwrap_or(0);
    for f in factors {
        // The factor's coefficient of a word v: x^k/k! for v = L^k; γ^weight(v)/len(v)! for a step.
        let x = match f {
            Factor::Letter(_, x) | Factor::Step(x) => *x,
        };
        let mut powers = vec![one.clone()];
        for k in 1..=top {
            powers.push(powers[k - 1].mul(x));
        }
        let inv_fact: Vec<BigRational> = (0..=max_len)
            .map(|k| BigRational::new(BigInt::one(), factorial(k)))
            .collect();
        let e = |v: &[u8]| -> Option<Poly> {
            match f {
                Factor::Letter(l, _) => v
                    .iter()
                    .all(|c| c == l)
                    .then(|| powers[v.len()].scale(&inv_fact[v.len()])),
                Factor::Step(_) => {
                    Some(powers[word_weight(comp(form), v)].scale(&inv_fact[v.len()]))
                }
            }
        };
        let mut next = HashMap::with_capacity(p.len());
        for w in &words {
            let mut acc = p[w].clone();
            for i in 0..w.len() {
                let u = &p[&w[..i]];
                if u.is_zero() {
                    continue;
                }
                if let Some(ev) = e(&w[i..]) {
                    acc = acc.add(&u.mul(&ev));
                }
            }
            next.insert(w.clone(), acc);
        }
        p = next;
    }
    p
}

/// The coefficient of `w` in `log P`: `Σ_k (−1)^{k+1}/k Σ P[w₁]⋯P[w_k]` over
/// the ways of cutting `w` into `k` nonempty consecutive pieces.
pub(crate) fn log_coefficient(p: &HashMap<Word, Poly>, w: &[u8], nvars: usize) -> Poly {
    let n = w.len();
    // s[k][i]: Σ over cuttings of w[i..] into k pieces of the products.
    let mut s: Vec<Vec<Poly>> = vec![vec![Poly::zero(nvars); n + 1]; n + 1];
    s[0][n] = Poly::constant(nvars, BigRational::one());
    for k in 1..=n {
        for i in (0..n).rev() {
            let mut acc = Poly::zero(nvars);
            for j in i + 1..=n {
                let rest = &s[k - 1][j];
                if rest.is_zero() {
                    continue;
                }
                let piece = &p[&w[i..j]];
                if !piece.is_zero() {
                    acc = acc.add(&piece.mul(rest));
                }
            }
            s[k][i] = acc;
        }
    }
    let mut out = Poly::zero(nvars);
    for (k, row) in s.iter().enumerate().skip(1) {
        let sign = if k % 2 == 1 { 1 } else { -1 };
        out = out.add(&row[0].scale(&BigRational::new(sign.into(), (k as i64).into())));
    }
    out
}

/// The family's parameters after the fixed values, the ties and the
/// consistency conditions: each parameter as a polynomial in the raw
/// parameters (fixed ones constant, tied ones replaced, the middle ones
/// solved for).
fn reduce(family: &Family, file: &str) -> Result<(Vec<String>, Vec<Poly>), FamilyError> {
    let layout = family.layout();
    let n = layout.names.len();
    let index = |name: &str| layout.names.iter().position(|m| m == name);
    let mut map: Vec<Poly> = (0..n).map(|i| Poly::var(n, i)).collect();
    let substitute_all = |map: &mut Vec<Poly>, i: usize, value: &Poly| {
        let mut subs: Vec<Poly> = (0..n).map(|j| Poly::var(n, j)).collect();
        subs[i] = value.clone();
        for m in map.iter_mut() {
            *m = m.substitute(&subs, n);
        }
    };
    for (name, value) in &family.fixed {
        let i = index(name).expect("validated");
        substitute_all(&mut map, i, &Poly::constant(n, value.clone()));
    }
    for (x, y) in &family.equal {
        let (i, j) = (index(x).expect("validated"), index(y).expect("validated"));
        let value = map[i].clone();
        substitute_all(&mut map, j, &value);
    }
    // Consistency: Σ drift = 1, Σ kick = 1 (or Σ γ = 1), solved for the
    // highest-numbered parameter occurring (the middle coefficient).
    let groups: Vec<(&str, &Vec<usize>)> = match family.form {
        Form::Composition => vec![("g", &layout.gamma)],
        Form::Aba | Form::Bab => vec![("a", &layout.drift), ("b", &layout.kick)],
    };
    for (letter, group) in groups {
        let mut sum = Poly::constant(n, -BigRational::one());
        for &i in group {
            sum = sum.add(&map[i]);
        }
        let vars = sum.variables();
        match vars.last() {
            None => {
                let c = sum.as_constant().expect("no variables");
                if !c.is_zero() {
                    return Err(FamilyError {
                        file: file.to_string(),
                        field: Some("fixed".into()),
                        message: format!(
                            "the fixed values make the {letter} coefficients sum to {}, not 1 (consistency)",
                            c + BigRational::one()
                        ),
                    });
                }
            }
            Some(&v) => {
                // sum is affine: sum = c·x_v + rest; x_v = −rest / c.
                let c = sum.derivative(v).as_constant().expect("affine");
                let rest = sum.sub(&Poly::var(n, v).scale(&c));
                let value = rest.scale(&(-BigRational::one() / c));
                substitute_all(&mut map, v, &value);
            }
        }
    }
    Ok((layout.names, map))
}

/// Build the system of a family; `file` names it in messages.
pub fn system(family: &Family, file: &str) -> Result<System, FamilyError> {
    family.validate(file)?;
    let layout = family.layout();
    let (names, map) = reduce(family, file)?;
    let n = names.len();
    // The unknowns: the raw parameters that still occur.
    let used: Vec<usize> = (0..n)
        .filter(|&i| map.iter().any(|m| m.variables().contains(&i)))
        .collect();
    let m = used.len();
    let mut subs = vec![Poly::zero(m); n];
    for (k, &i) in used.iter().enumerate() {
        subs[i] = Poly::var(m, k);
    }
    let params: Vec<Poly> = map.iter().map(|p| p.substitute(&subs, m)).collect();
    let unknown_names: Vec<String> = used.iter().map(|&i| names[i].clone()).collect();
    let drift: Vec<Poly> = layout.drift.iter().map(|&i| params[i].clone()).collect();
    let kick: Vec<Poly> = layout.kick.iter().map(|&i| params[i].clone()).collect();
    let gamma: Vec<Poly> = layout.gamma.iter().map(|&i| params[i].clone()).collect();
    let factors = factors(family.form, &drift, &kick, &gamma);
    let p_order = family.order;
    // The degree up to which a Lie term with `j` letters B is imposed: the
    // classical order for every j, or the generalised order's p_j.
    let imposed = |w: &[u8]| -> usize {
        if family.generalised.is_empty() {
            return p_order;
        }
        let j = w.iter().filter(|&&l| l == 1).count().max(1);
        let g = &family.generalised;
        g[(j - 1).min(g.len() - 1)]
    };
    let top = family
        .generalised
        .iter()
        .copied()
        .max()
        .unwrap_or(p_order)
        .max(p_order)
        + 1;
    // Which words the product needs: all of them for a classical order; for
    // a generalised order, a word with j letters B only up to the length
    // M_j = max over k ≥ j of (p_k + 1), the longest Lie term with at least j
    // letters B that is imposed or measured. M_j does not increase with j,
    // so every factor (substring) of a kept word is kept, as the product and
    // the logarithm need; at (10, 4) this keeps ~50 words of the 4094.
    let reach = |j: usize| -> usize {
        if family.generalised.is_empty() {
            return top;
        }
        let g = &family.generalised;
        (j.max(1)..=top)
            .map(|k| g[(k - 1).min(g.len() - 1)] + 1)
            .max()
            .unwrap_or(top)
            .min(top)
            .max(if j == 0 { top } else { 0 })
    };
    let keep = |w: &[u8]| -> bool {
        comp(family.form) || w.len() <= reach(w.iter().filter(|&&l| l == 1).count())
    };
    let prod = product(family.form, &factors, top, m, &keep);
    let parts = Parts {
        names,
        params,
        unknown_names,
        drift,
        kick,
        gamma,
    };
    if family.processed {
        // A processed kernel: the effective-order conditions instead of the
        // classical ones (crate::effective), from the whole of log K.
        let letters = if comp(family.form) {
            crate::effective::Letters::Composition
        } else {
            crate::effective::Letters::DriftKick
        };
        let mut log_k: crate::effective::Series = HashMap::new();
        for n in 1..=top {
            for w in words_of_weight(comp(family.form), n) {
                if !keep(&w) {
                    continue;
                }
                let c = log_coefficient(&prod, &w, m);
                if !c.is_zero() {
                    log_k.insert(w, c);
                }
            }
        }
        // (A generalised order is validated non-increasing for a
        // processed kernel, so `keep` is `Reach`'s truncation.)
        let elim = if family.generalised.is_empty() {
            crate::effective::eliminate(letters, &log_k, p_order, m, false)
        } else {
            let reach = crate::effective::Reach::new(&family.generalised);
            crate::effective::eliminate_near(reach, &log_k, m, false)
        }
        .map_err(|e| FamilyError {
            file: file.to_string(),
            field: None,
            message: e.to_string(),
        })?;
        let to_condition = |t: crate::effective::Term| Condition {
            word: t.word,
            degree: t.weight,
            poly: t.poly,
        };
        let conditions = elim.conditions.into_iter().map(to_condition).collect();
        let error_terms = elim.errors.into_iter().map(to_condition).collect();
        return finish(family, file, parts, conditions, error_terms);
    }
    let mut conditions = Vec::new();
    let mut error_terms = Vec::new();
    for degree in 1..=top {
        for w in words_of_weight(comp(family.form), degree) {
            if !is_lyndon(&w) || !keep(&w) {
                continue;
            }
            let mut poly = log_coefficient(&prod, &w, m);
            // Target: 1 for the letters of weight one (A, B, Y₁).
            if degree == 1 {
                poly = poly.sub(&Poly::constant(m, BigRational::one()));
            }
            let label = word_label(comp(family.form), &w);
            if degree == 1 || degree % 2 == 0 {
                // Consistency was solved for; even degrees vanish for a
                // palindrome. Both are checked, not assumed.
                if !poly.is_zero() {
                    return Err(FamilyError {
                        file: file.to_string(),
                        field: None,
                        message: format!(
                            "internal error: the condition for {label} (degree {degree}) does not vanish identically for this symmetric family; please report it"
                        ),
                    });
                }
                continue;
            }
            let limit = imposed(&w);
            if degree > limit + 1 || (family.rkn && degree >= 5 && degree <= limit) {
                // (RKN conditions of degree ≥ 5 are the Lyndon-basis
                // coordinates outside the ideal, added below.)
                continue;
            }
            if let Some(c) = poly.as_constant()
                && degree <= limit
                && !c.is_zero()
            {
                return Err(FamilyError {
                    file: file.to_string(),
                    field: None,
                    message: format!(
                        "the fixed values leave the degree-{degree} condition for {label} equal to {c}, so order {} is impossible in this family",
                        family.order_text()
                    ),
                });
            }
            if poly.is_zero() {
                continue;
            }
            let cond = Condition {
                word: label,
                degree,
                poly,
            };
            if degree <= limit {
                conditions.push(cond);
            } else {
                error_terms.push(cond);
            }
        }
    }
    if family.rkn {
        for degree in (5..=p_order).step_by(2) {
            let words: Vec<Word> = words_of_weight(false, degree)
                .into_iter()
                .filter(|w| is_lyndon(w))
                .collect();
            let e: Vec<Poly> = words.iter().map(|w| log_coefficient(&prod, w, m)).collect();
            let terms =
                lyndon_basis_terms(false, degree, &words, &e, true, m).map_err(|message| {
                    FamilyError {
                        file: file.to_string(),
                        field: Some("rkn".into()),
                        message,
                    }
                })?;
            conditions.extend(terms.into_iter().filter(|c| !c.poly.is_zero()));
        }
    }
    if family.error_basis == ErrorBasis::Brackets {
        let degree = p_order + 1;
        let words: Vec<Word> = words_of_weight(comp(family.form), degree)
            .into_iter()
            .filter(|w| is_lyndon(w))
            .collect();
        let e: Vec<Poly> = words.iter().map(|w| log_coefficient(&prod, w, m)).collect();
        error_terms = lyndon_basis_terms(comp(family.form), degree, &words, &e, family.rkn, m)
            .map_err(|message| FamilyError {
                file: file.to_string(),
                field: Some("error_basis".into()),
                message,
            })?;
        error_terms.retain(|c| !c.poly.is_zero());
    }
    finish(family, file, parts, conditions, error_terms)
}

/// What a system is made of besides its conditions.
struct Parts {
    names: Vec<String>,
    params: Vec<Poly>,
    unknown_names: Vec<String>,
    drift: Vec<Poly>,
    kick: Vec<Poly>,
    gamma: Vec<Poly>,
}

/// The system, once its conditions are known: refused when they outnumber
/// the unknowns.
fn finish(
    family: &Family,
    file: &str,
    parts: Parts,
    conditions: Vec<Condition>,
    error_terms: Vec<Condition>,
) -> Result<System, FamilyError> {
    let Parts {
        names,
        params,
        unknown_names,
        drift,
        kick,
        gamma,
    } = parts;
    let m = unknown_names.len();
    let p_order = family.order;
    if conditions.len() > m {
        return Err(FamilyError {
            file: file.to_string(),
            field: Some("stages".into()),
            message: format!(
                "order {} imposes {} conditions ({}) on {m} unknowns ({}): too few stages",
                family.order_text(),
                conditions.len(),
                conditions
                    .iter()
                    .map(|c| c.word.clone())
                    .collect::<Vec<_>>()
                    .join(", "),
                unknown_names.join(", ")
            ),
        });
    }
    let parameters = names.iter().cloned().zip(params).collect();
    Ok(System {
        form: family.form,
        order: p_order,
        generalised: family.generalised.clone(),
        stages: family.stages,
        names: unknown_names,
        parameters,
        drift,
        kick,
        gamma,
        conditions,
        error_terms,
        rkn: family.rkn,
    })
}

/// A polynomial in non-commuting letters with rational coefficients.
type Assoc = HashMap<Word, BigRational>;

fn assoc_bracket(x: &Assoc, y: &Assoc) -> Assoc {
    let mut out: Assoc = HashMap::new();
    for (u, a) in x {
        for (v, b) in y {
            let p = a * b;
            let mut uv = u.clone();
            uv.extend_from_slice(v);
            let mut vu = v.clone();
            vu.extend_from_slice(u);
            *out.entry(uv).or_insert_with(BigRational::zero) += &p;
            *out.entry(vu).or_insert_with(BigRational::zero) -= &p;
        }
    }
    out.retain(|_, c| !c.is_zero());
    out
}

/// The standard bracketing of a Lyndon word `w = uv`, `v` its longest proper
/// Lyndon suffix: `P_w = [P_u, P_v]`; and whether the bracketing has the
/// RKN generator `ABBB = [[[A,B],B],B]` as a sub-bracket.
fn standard_bracketing(w: &[u8]) -> (Assoc, bool) {
    if w.len() == 1 {
        return (HashMap::from([(w.to_vec(), BigRational::one())]), false);
    }
    let split = (1..w.len())
        .find(|&i| is_lyndon(&w[i..]) || w.len() - i == 1)
        .expect("a one-letter suffix is Lyndon");
    let (pu, iu) = standard_bracketing(&w[..split]);
    let (pv, iv) = standard_bracketing(&w[split..]);
    (assoc_bracket(&pu, &pv), iu || iv || w == [0, 1, 1, 1])
}

/// Exact rank of a rational matrix (rows), by elimination.
fn rational_rank(mut rows: Vec<Vec<BigRational>>) -> usize {
    let mut rank = 0;
    let cols = rows.first().map_or(0, Vec::len);
    for col in 0..cols {
        let Some(piv) = (rank..rows.len()).find(|&r| !rows[r][col].is_zero()) else {
            continue;
        };
        rows.swap(rank, piv);
        for r in rank + 1..rows.len() {
            if rows[r][col].is_zero() {
                continue;
            }
            let f = &rows[r][col] / &rows[rank][col];
            let pivot = rows[rank].clone();
            for (x, y) in rows[r].iter_mut().zip(&pivot).skip(col) {
                *x -= &f * y;
            }
        }
        rank += 1;
    }
    rank
}

/// The error terms as coordinates in the Lyndon basis: `words` are the
/// Lyndon words of one degree and `e` the Lie element's coefficients on
/// them; with `P_u` the standard bracketing of `u`, the element is
/// `Σ c_u P_u` with `e_w = Σ_u c_u ⟨w, P_u⟩`, a unitriangular system solved
/// exactly for `c`. With `rkn`, the coordinates on basis elements inside the
/// ideal generated by `[B,[B,[B,A]]]` are dropped; that this leaves the
/// quotient's coordinates is checked: the dropped elements must be as many
/// as the ideal's dimension at this degree (computed from the brackets
/// `[Y₁,[Y₂,…,[ABBB]]]`).
pub fn lyndon_basis_terms(
    comp: bool,
    degree: usize,
    words: &[Word],
    e: &[Poly],
    rkn: bool,
    nvars: usize,
) -> Result<Vec<Condition>, String> {
    let n = words.len();
    let brackets: Vec<(Assoc, bool)> = words.iter().map(|w| standard_bracketing(w)).collect();
    // t[i][j] = ⟨words[i], P_{words[j]}⟩.
    let t: Vec<Vec<BigRational>> = words
        .iter()
        .map(|w| {
            brackets
                .iter()
                .map(|(p, _)| p.get(w).cloned().unwrap_or_else(BigRational::zero))
                .collect()
        })
        .collect();
    // c = T⁻¹ e, column by column of T⁻¹.
    let mut inv = vec![vec![BigRational::zero(); n]; n];
    for j in 0..n {
        let mut unit = vec![BigRational::zero(); n];
        unit[j] = BigRational::one();
        let col = crate::linalg::solve_rational(&t, &unit)
            .ok_or("internal error: the Lyndon basis matrix is singular")?;
        for i in 0..n {
            inv[i][j] = col[i].clone();
        }
    }
    if rkn {
        let dropped = brackets.iter().filter(|(_, i)| *i).count();
        let mut rows = Vec::new();
        if degree >= 4 {
            let generator = standard_bracketing(&[0, 1, 1, 1]).0;
            let mut level = vec![generator];
            for _ in 4..degree {
                let mut next = Vec::new();
                for x in &level {
                    for l in 0..2u8 {
                        let y = HashMap::from([(vec![l], BigRational::one())]);
                        next.push(assoc_bracket(&y, x));
                    }
                }
                level = next;
            }
            for x in &level {
                rows.push(
                    words
                        .iter()
                        .map(|w| x.get(w).cloned().unwrap_or_else(BigRational::zero))
                        .collect(),
                );
            }
        }
        let dim = rational_rank(rows);
        if dim != dropped {
            return Err(format!(
                "the RKN ideal has dimension {dim} at degree {degree}, but {dropped} Lyndon basis elements contain ABBB: the quotient's coordinates are not the remaining ones here"
            ));
        }
    }
    let mut out = Vec::new();
    for (u, (_, in_ideal)) in brackets.iter().enumerate() {
        if rkn && *in_ideal {
            continue;
        }
        let mut poly = Poly::zero(nvars);
        for (w, ew) in e.iter().enumerate() {
            if !inv[u][w].is_zero() {
                poly = poly.add(&ew.scale(&inv[u][w]));
            }
        }
        out.push(Condition {
            word: format!("P({})", word_label(comp, &words[u])),
            degree,
            poly,
        });
    }
    Ok(out)
}

/// `|x|` of a rational, for messages.
pub fn abs(x: &BigRational) -> BigRational {
    x.abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lyndon_words() {
        assert!(is_lyndon(&[0, 0, 1]));
        assert!(is_lyndon(&[0, 1, 1]));
        assert!(!is_lyndon(&[0, 1, 0]));
        assert!(!is_lyndon(&[0, 0]));
        let n5 = words_of_weight(comp(Form::Aba), 5)
            .into_iter()
            .filter(|w| is_lyndon(w))
            .count();
        assert_eq!(n5, 6);
        let w5: Vec<Word> = words_of_weight(comp(Form::Composition), 5)
            .into_iter()
            .filter(|w| is_lyndon(w))
            .collect();
        assert_eq!(w5, vec![vec![0, 0, 1], vec![2]]);
    }

    #[test]
    fn triple_jump_conditions() {
        let f = Family::new("y", Form::Composition, 3, 4);
        let s = system(&f, "test").unwrap();
        assert_eq!(s.names, ["g1"]);
        assert_eq!(s.conditions.len(), 1);
        assert_eq!(s.conditions[0].word, "Y₃");
        // 2g³ + (1 − 2g)³ = −6g³ + 12g² − 6g + 1.
        assert_eq!(
            s.conditions[0].poly.to_text(&s.names),
            "-6*g1^3 + 12*g1^2 - 6*g1 + 1"
        );
        assert_eq!(s.error_terms.len(), 2);
    }
}
