//! Effective order: the conditions on a processed kernel, and the
//! conjugator its processor must approximate.
//!
//! **Processing.** A kernel `K` stepped as `χ Kⁿ χ⁻¹`, the processor `χ`
//! applied only at output and `χ⁻¹` once on entry, has the errors of the one
//! method `χ K χ⁻¹` (Butcher 1969; López-Marcos, Sanz-Serna & Skeel 1996;
//! Blanes, Casas & Ros 1999). Its logarithm is `exp(ad_Z) log K` with
//! `−Z = log χ` (maps in the order applied, as the conditions' products are
//! formed), so what `χ` can change at weight `n` is `[Z_{n−1}, Y₁]` plus
//! terms fixed by lower weights: the image of `ad_{Y₁}`. The kernel's
//! *effective-order conditions* are what remains: at each weight `n`, the
//! part of the weight-`n` Lie element outside that image.
//!
//! **The elimination.** Weight by weight (`n = 2, 3, …`): the weight-`n`
//! part of the current series, as coordinates `e` on the Lyndon words of
//! weight `n`, is split as `e = M c + r`, `M`'s columns the coordinates of
//! `[P_u, Y₁]` for the Lyndon basis `P_u` of weight `n − 1` (standard
//! bracketing; `ad_{Y₁}` is injective there, which is checked). Pivot rows
//! of `M` give `c` exactly and `r` vanishes on them; the other rows of `r`
//! are the conditions (independent functionals that vanish exactly when the
//! part lies in the image). Then `X = −Σ c_u P_u` and the series becomes
//! `exp(ad_X)` of itself, which clears weight `n` up to `r`; the conjugators
//! compose to `exp(Z) = ⋯ exp(X₃) exp(X₂)`. Off the conditions, `c` depends
//! on which pivot rows were taken, and so do the higher conditions; on them
//! every choice gives the same, the unique `X` (injectivity), so the zero set
//! is the effective-order set. The error measured at weight `p + 1` is the
//! orthogonal projection of `e` onto the complement of the image (in the
//! Lyndon-word coordinates), which no choice of rows changes.
//!
//! **The letters** ([`Letters`]): those of a composition of a symmetric
//! basic method, `Y₁, Y₃, Y₅, …` with `Y_k` of weight `k` (see
//! [`crate::conditions`]), or those of a drift–kick sequence, `A` and `B`
//! of weight one, whose kernel's weight-one part is `Y₁ = A + B` (Blanes,
//! Casas & Ros 1999 process such kernels). The elimination is the same;
//! only the letters, their weights and `Y₁` differ.

use std::collections::HashMap;

use num_rational::BigRational;
use num_traits::{One, Zero};

use crate::linalg::solve_rational;
use crate::poly::Poly;
use tableau::certificate::{factorial, is_lyndon, word_label, word_weight, words_of_weight};

/// A word in the letters `Y₁ = 0, Y₃ = 1, …` or `A = 0, B = 1` ([`Letters`]).
pub type Word = Vec<u8>;

/// A series in the free associative algebra, truncated by weight, with
/// polynomial coefficients; absent words have coefficient zero.
pub type Series = HashMap<Word, Poly>;

/// One condition or error term: the Lyndon word's label, its weight, the
/// polynomial.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Term {
    pub word: String,
    pub weight: usize,
    pub poly: Poly,
}

/// What the elimination gives.
#[derive(Clone, Debug)]
pub struct Elimination {
    /// The effective-order conditions of weights `2..=p` that are not
    /// identically zero.
    pub conditions: Vec<Term>,
    /// The part of weight `p + 1` no processor removes (orthogonal
    /// projection; dependent coordinates, for the objective `Σ e²`).
    pub errors: Vec<Term>,
    /// `Z`, up to weight `p` (with `want_conjugator`): `log χ` must be `−Z`
    /// there for the processed method to have effective order `p` and the
    /// least error at `p + 1`.
    pub conjugator: Series,
}

/// Why the elimination could not be done.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum EffectiveError {
    /// A condition is a nonzero constant: the family's fixed values make the
    /// effective order impossible.
    #[error(
        "the fixed values leave the weight-{weight} effective condition for {word} equal to {value}, so effective order {order} is impossible in this family"
    )]
    Impossible {
        word: String,
        weight: usize,
        value: String,
        order: String,
    },
    /// A check that must hold for a symmetric kernel did not.
    #[error("internal error: {0}; please report it")]
    Internal(String),
}

/// The alphabet a kernel's series is written in: which letters, their
/// weights, and the weight-one element `Y₁` the processor conjugates
/// around (the kernel's log is `h·Y₁ + …` after consistency).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Letters {
    /// `Y₁ = 0, Y₃ = 1, …` of weights 1, 3, …: a composition of a
    /// symmetric basic method; `Y₁` is the letter `0`.
    Composition,
    /// `A = 0, B = 1`, each of weight one: a drift–kick sequence; `Y₁` is
    /// `A + B`, so `ad_{Y₁}` kills `A + B` at weight one and the image from
    /// there is spanned by `[A, A + B] = [A, B]`.
    DriftKick,
    /// `A` and `B` as in [`Letters::DriftKick`], for `H = A + εB`: a word
    /// with `j ≥ 1` letters `B` is kept only up to the length
    /// [`Reach::of`]`(j)`, so a product keeps exactly the coefficients of
    /// the kept words (the kept words are closed under taking factors).
    NearIntegrable(Reach),
}

/// The longest word kept with `j` letters `B`, for `j = 1, 2, …` (the last
/// entry for every larger `j`): for a generalised order `(p₁, p₂, …)`
/// (non-increasing) `p_j + 1`, the terms imposed and the first measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reach {
    len: [u8; 16],
    n: u8,
}

impl Reach {
    /// From a non-increasing generalised order `(p₁, p₂, …)`, at most 16
    /// entries of at most 254.
    pub fn new(degrees: &[usize]) -> Reach {
        assert!(!degrees.is_empty() && degrees.len() <= 16);
        assert!(degrees.windows(2).all(|w| w[0] >= w[1]));
        let mut len = [0u8; 16];
        for (l, &d) in len.iter_mut().zip(degrees) {
            *l = u8::try_from(d + 1).expect("a degree below 255");
        }
        Reach {
            len,
            n: degrees.len() as u8,
        }
    }

    /// The degree `p_j` imposed on the terms with `j ≥ 1` letters `B`.
    pub fn degree(&self, j: usize) -> usize {
        let i = j.clamp(1, self.n as usize) - 1;
        self.len[i] as usize - 1
    }

    /// The longest word kept with `j` letters `B` (`j = 0`: unbounded).
    pub fn of(&self, j: usize) -> usize {
        if j == 0 {
            usize::MAX
        } else {
            self.degree(j) + 1
        }
    }

    /// The longest word kept at all.
    pub fn top(&self) -> usize {
        self.of(1)
    }

    /// `(p₁, p₂, …)` as a claim writes it.
    pub fn text(&self) -> String {
        let items: Vec<String> = (1..=self.n as usize)
            .map(|j| self.degree(j).to_string())
            .collect();
        format!("({})", items.join(", "))
    }
}

/// The number of letters `B` in a word of `A = 0`, `B = 1`.
pub fn b_count(w: &[u8]) -> usize {
    w.iter().filter(|&&l| l == 1).count()
}

impl Letters {
    fn weighted(self) -> bool {
        self == Letters::Composition
    }

    /// Whether a word is kept in a truncated product.
    fn keeps(self, w: &[u8]) -> bool {
        match self {
            Letters::NearIntegrable(r) => w.len() <= r.of(b_count(w)),
            _ => true,
        }
    }

    fn weight(self, w: &[u8]) -> usize {
        word_weight(self.weighted(), w)
    }

    fn lyndon_words(self, n: usize) -> Vec<Word> {
        words_of_weight(self.weighted(), n)
            .into_iter()
            .filter(|w| is_lyndon(w) && self.keeps(w))
            .collect()
    }

    /// `Y₁` as a series.
    fn y1(self) -> Series {
        let one = || Poly::constant(0, BigRational::one());
        match self {
            Letters::Composition => HashMap::from([(vec![0], one())]),
            Letters::DriftKick | Letters::NearIntegrable(_) => {
                HashMap::from([(vec![0], one()), (vec![1], one())])
            }
        }
    }

    /// The Lyndon words of weight `n` whose basis elements span a
    /// complement of `ker ad_{Y₁}` there: all of them above weight one (in
    /// a free Lie algebra the centraliser of a weight-one element is its
    /// span), and at weight one all but the letter `Y₁` (compositions) or
    /// `B` (drift–kick: `A` alone spans a complement of `A + B`).
    fn below(self, n: usize) -> Vec<Word> {
        let dropped: &[u8] = match self {
            Letters::Composition => &[0],
            Letters::DriftKick | Letters::NearIntegrable(_) => &[1],
        };
        self.lyndon_words(n)
            .into_iter()
            .filter(|u| n != 1 || u.as_slice() != dropped)
            .collect()
    }
}

/// `a·b`, truncated at weight `top`.
pub fn mul(letters: Letters, a: &Series, b: &Series, top: usize, nvars: usize) -> Series {
    let mut out: Series = HashMap::new();
    for (u, x) in a {
        if x.is_zero() {
            continue;
        }
        let wu = letters.weight(u);
        for (v, y) in b {
            if y.is_zero() || wu + letters.weight(v) > top {
                continue;
            }
            let mut uv = u.clone();
            uv.extend_from_slice(v);
            if !letters.keeps(&uv) {
                continue;
            }
            let entry = out.entry(uv).or_insert_with(|| Poly::zero(nvars));
            *entry = entry.add(&x.mul(y));
        }
    }
    out.retain(|_, p| !p.is_zero());
    out
}

/// `a + b`, or `a − b` with `negate`.
fn combine(a: &Series, b: &Series, nvars: usize, negate: bool) -> Series {
    let mut out = a.clone();
    for (w, y) in b {
        let entry = out.entry(w.clone()).or_insert_with(|| Poly::zero(nvars));
        *entry = if negate { entry.sub(y) } else { entry.add(y) };
    }
    out.retain(|_, p| !p.is_zero());
    out
}

fn sub(a: &Series, b: &Series, nvars: usize) -> Series {
    combine(a, b, nvars, true)
}

fn add(a: &Series, b: &Series, nvars: usize) -> Series {
    combine(a, b, nvars, false)
}

fn scale(a: &Series, k: &BigRational) -> Series {
    a.iter().map(|(w, p)| (w.clone(), p.scale(k))).collect()
}

/// `[a, b]`, truncated at weight `top`.
pub fn bracket(letters: Letters, a: &Series, b: &Series, top: usize, nvars: usize) -> Series {
    sub(
        &mul(letters, a, b, top, nvars),
        &mul(letters, b, a, top, nvars),
        nvars,
    )
}

/// `exp(ad_x) l = l + [x, l] + [x, [x, l]]/2 + …`, truncated at `top`
/// (`x` has no weight-0 part, so the sum is finite).
pub fn conjugate(letters: Letters, x: &Series, l: &Series, top: usize, nvars: usize) -> Series {
    let mut out = l.clone();
    let mut term = l.clone();
    for k in 1..=top {
        term = bracket(letters, x, &term, top, nvars);
        if term.is_empty() {
            break;
        }
        let inv = BigRational::new(One::one(), factorial(k));
        out = add(&out, &scale(&term, &inv), nvars);
    }
    out
}

/// `exp(x)` (with the empty word), truncated at `top`.
pub fn exp(letters: Letters, x: &Series, top: usize, nvars: usize) -> Series {
    let mut out: Series = HashMap::from([(Vec::new(), Poly::constant(nvars, BigRational::one()))]);
    let mut term = out.clone();
    for k in 1..=top {
        term = scale(
            &mul(letters, &term, x, top, nvars),
            &BigRational::new(One::one(), k.into()),
        );
        if term.is_empty() {
            break;
        }
        out = add(&out, &term, nvars);
    }
    out
}

/// `log(s)` for `s` with constant term 1, truncated at `top`.
pub fn log(letters: Letters, s: &Series, top: usize, nvars: usize) -> Series {
    let mut y = s.clone();
    y.remove(&Vec::new());
    let mut out: Series = HashMap::new();
    let mut power = y.clone();
    for k in 1..=top {
        if power.is_empty() {
            break;
        }
        let sign = if k % 2 == 1 { 1 } else { -1 };
        out = add(
            &out,
            &scale(&power, &BigRational::new(sign.into(), (k as i64).into())),
            nvars,
        );
        power = mul(letters, &power, &y, top, nvars);
    }
    out
}

/// The standard bracketing of a Lyndon word, as a series with constant
/// coefficients.
fn basis_element(letters: Letters, w: &[u8], nvars: usize) -> Series {
    if w.len() == 1 {
        return HashMap::from([(w.to_vec(), Poly::constant(nvars, BigRational::one()))]);
    }
    let split = (1..w.len())
        .find(|&i| is_lyndon(&w[i..]))
        .expect("a one-letter suffix is Lyndon");
    let top = letters.weight(w);
    bracket(
        letters,
        &basis_element(letters, &w[..split], nvars),
        &basis_element(letters, &w[split..], nvars),
        top,
        nvars,
    )
}

fn constant(p: &Poly) -> BigRational {
    p.as_constant()
        .expect("a basis element has constant coefficients")
}

/// Pivot rows of a rational matrix (rows × cols) of full column rank, or
/// `None` when the rank is short.
fn pivot_rows(m: &[Vec<BigRational>], cols: usize) -> Option<Vec<usize>> {
    // Eliminate on the transpose: a column basis of Mᵀ is a row basis of M.
    let mut rows: Vec<Vec<BigRational>> = m.to_vec();
    let mut chosen = Vec::new();
    let mut basis: Vec<(usize, Vec<BigRational>)> = Vec::new(); // (pivot col, reduced row)
    for (i, row) in rows.iter_mut().enumerate() {
        let mut r = row.clone();
        for (col, b) in &basis {
            if !r[*col].is_zero() {
                let f = &r[*col] / &b[*col];
                for (x, y) in r.iter_mut().zip(b) {
                    *x -= &f * y;
                }
            }
        }
        if let Some(col) = (0..cols).find(|&c| !r[c].is_zero()) {
            basis.push((col, r));
            chosen.push(i);
        }
    }
    (chosen.len() == cols).then_some(chosen)
}

/// Eliminate the processor from the series `l` (`log K`, weight-one part
/// `Y₁` after consistency, every word up to weight `p + 1` present): the
/// effective-order conditions of weights `2..=p`, the error of weight
/// `p + 1`, and, with `want_conjugator`, `Z` up to weight `p` (for a kernel
/// at its printed values, whose conditions are then constants near zero and
/// are not returned).
pub fn eliminate(
    letters: Letters,
    l: &Series,
    p: usize,
    nvars: usize,
    want_conjugator: bool,
) -> Result<Elimination, EffectiveError> {
    let top = p + 1;
    let mut l = l.clone();
    let mut conditions = Vec::new();
    let mut errors = Vec::new();
    let mut z_exp: Series =
        HashMap::from([(Vec::new(), Poly::constant(nvars, BigRational::one()))]);
    for n in 2..=top {
        let words = letters.lyndon_words(n);
        // ad(Y₁) kills Y₁ alone: the image comes from the other elements.
        let below = letters.below(n - 1);
        let e: Vec<Poly> = words
            .iter()
            .map(|w| l.get(w).cloned().unwrap_or_else(|| Poly::zero(nvars)))
            .collect();
        let basis: Vec<Series> = below.iter().map(|u| basis_element(letters, u, 0)).collect();
        let images: Vec<Series> = basis
            .iter()
            .map(|b| bracket(letters, b, &letters.y1(), n, 0))
            .collect();
        // m[i][j]: coefficient of words[i] in [P_{below[j]}, Y₁].
        let m: Vec<Vec<BigRational>> = words
            .iter()
            .map(|w| {
                images
                    .iter()
                    .map(|s| s.get(w).map(constant).unwrap_or_else(BigRational::zero))
                    .collect()
            })
            .collect();
        let cols = below.len();
        let pivots = pivot_rows(&m, cols).ok_or_else(|| {
            EffectiveError::Internal(format!(
                "ad(Y₁) is not injective from weight {} to weight {n}",
                n - 1
            ))
        })?;
        // c = M_R⁻¹ e_R.
        let c = solve_on_pivots(&m, &e, &pivots, nvars)?;
        if n <= p {
            for i in (0..words.len()).filter(|i| !pivots.contains(i)) {
                let r = residual(&m[i], &e[i], &c);
                let label = word_label(letters.weighted(), &words[i]);
                push_condition(&mut conditions, label, n, r, want_conjugator, || {
                    p.to_string()
                })?;
            }
        } else {
            // The orthogonal projection onto the complement of M's range:
            // r = e − M (MᵀM)⁻¹ Mᵀ e.
            let d = least_squares(&m, &e, nvars)?;
            for (i, w) in words.iter().enumerate() {
                let r = residual(&m[i], &e[i], &d);
                if !r.is_zero() {
                    errors.push(Term {
                        word: word_label(letters.weighted(), w),
                        weight: n,
                        poly: r,
                    });
                }
            }
        }
        clear(
            letters,
            &basis,
            &c,
            (n, top, p),
            nvars,
            &mut l,
            want_conjugator.then_some(&mut z_exp),
        );
    }
    Ok(Elimination {
        conditions,
        errors,
        conjugator: conjugator(letters, want_conjugator.then_some(&z_exp), p, nvars),
    })
}

/// The solution `c` of `M c = e` on the pivot rows (exact), for the
/// columns of a full-column-rank `M`.
fn solve_on_pivots(
    m: &[Vec<BigRational>],
    e: &[Poly],
    pivots: &[usize],
    nvars: usize,
) -> Result<Vec<Poly>, EffectiveError> {
    let cols = pivots.len();
    let mr: Vec<Vec<BigRational>> = pivots.iter().map(|&i| m[i].clone()).collect();
    let mut c: Vec<Poly> = vec![Poly::zero(nvars); cols];
    for (k, &i) in pivots.iter().enumerate() {
        let mut unit = vec![BigRational::zero(); cols];
        unit[k] = BigRational::one();
        let col = solve_rational(&mr, &unit)
            .ok_or_else(|| EffectiveError::Internal("singular pivot block".into()))?;
        for j in 0..cols {
            if !col[j].is_zero() {
                c[j] = c[j].add(&e[i].scale(&col[j]));
            }
        }
    }
    Ok(c)
}

/// The least-squares solution `c = (MᵀM)⁻¹Mᵀe` of `M c ≈ e` (exact).
fn least_squares(
    m: &[Vec<BigRational>],
    e: &[Poly],
    nvars: usize,
) -> Result<Vec<Poly>, EffectiveError> {
    let cols = m.first().map_or(0, Vec::len);
    let mtm: Vec<Vec<BigRational>> = (0..cols)
        .map(|a| {
            (0..cols)
                .map(|b| {
                    m.iter()
                        .map(|r| &r[a] * &r[b])
                        .fold(BigRational::zero(), |s, x| s + x)
                })
                .collect()
        })
        .collect();
    let mut d: Vec<Poly> = vec![Poly::zero(nvars); cols];
    for k in 0..cols {
        let mut unit = vec![BigRational::zero(); cols];
        unit[k] = BigRational::one();
        let col = solve_rational(&mtm, &unit)
            .ok_or_else(|| EffectiveError::Internal("singular MᵀM".into()))?;
        let mte_k = m.iter().zip(e).fold(Poly::zero(nvars), |s, (r, x)| {
            if r[k].is_zero() {
                s
            } else {
                s.add(&x.scale(&r[k]))
            }
        });
        for j in 0..cols {
            if !col[j].is_zero() {
                d[j] = d[j].add(&mte_k.scale(&col[j]));
            }
        }
    }
    Ok(d)
}

/// `e − M_i·c` for row `M_i`.
fn residual(m_i: &[BigRational], e_i: &Poly, c: &[Poly]) -> Poly {
    let mut r = e_i.clone();
    for (mij, cj) in m_i.iter().zip(c) {
        if !mij.is_zero() && !cj.is_zero() {
            r = r.sub(&cj.scale(mij));
        }
    }
    r
}

/// Keep the residual `r` of the weight-`n` term `label` as a condition, or
/// refuse: an even weight must vanish for a symmetric kernel, and a
/// nonzero constant makes the order (`order()`) impossible, unless the
/// kernel is given by its printed values (`at_values`: its conditions hold
/// to the printed digits only).
fn push_condition(
    conditions: &mut Vec<Term>,
    label: String,
    n: usize,
    r: Poly,
    at_values: bool,
    order: impl Fn() -> String,
) -> Result<(), EffectiveError> {
    if r.is_zero() {
        return Ok(());
    }
    if n.is_multiple_of(2) {
        return Err(EffectiveError::Internal(format!(
            "the even-weight effective term {label} (weight {n}) does not vanish for a symmetric kernel"
        )));
    }
    if let Some(v) = r.as_constant() {
        if at_values {
            return Ok(());
        }
        return Err(EffectiveError::Impossible {
            word: label,
            weight: n,
            value: v.to_string(),
            order: order(),
        });
    }
    conditions.push(Term {
        word: label,
        weight: n,
        poly: r,
    });
    Ok(())
}

/// `X = −Σ c_u P_u` clears the image part of weight `n`: conjugate `l` by
/// it (below `top`) and, with `z_exp`, compose it into the conjugator
/// (truncated at `p`).
fn clear(
    letters: Letters,
    basis: &[Series],
    c: &[Poly],
    (n, top, p): (usize, usize, usize),
    nvars: usize,
    l: &mut Series,
    z_exp: Option<&mut Series>,
) {
    let mut x: Series = HashMap::new();
    for (cj, b) in c.iter().zip(basis) {
        if cj.is_zero() {
            continue;
        }
        for (w, k) in b {
            let entry = x.entry(w.clone()).or_insert_with(|| Poly::zero(nvars));
            *entry = entry.sub(&cj.scale(&constant(k)));
        }
    }
    x.retain(|_, q| !q.is_zero());
    if x.is_empty() {
        return;
    }
    if n < top {
        *l = conjugate(letters, &x, l, top, nvars);
    }
    if let Some(z) = z_exp {
        *z = mul(letters, &exp(letters, &x, p, nvars), z, p, nvars);
    }
}

/// `Z = log exp(Z)`, up to weight `p`, or nothing.
fn conjugator(letters: Letters, z_exp: Option<&Series>, p: usize, nvars: usize) -> Series {
    z_exp.map_or_else(HashMap::new, |z| log(letters, z, p, nvars))
}

/// The effective generalised order of a symmetric drift–kick kernel for
/// `H = A + εB`: [`eliminate`] for the terms `εʲhⁿ` with `j` letters `B`,
/// imposed up to the degree `p_j` of `reach` (non-increasing) and measured
/// at `p_j + 1`.
///
/// **Blocks.** `[P, A + B]` for a basis element `P` with `j ≥ 1` letters
/// `B` has a part with `j` (`[P, A]`) and one with `j + 1` (`[P, B]`), and
/// `ad_A` is injective on the elements with a `B`; so weight by weight the
/// blocks are taken in increasing `j`, the processor's part with `j`
/// letters fixed by the kernel's `εʲ` terms after the shift the part with
/// `j − 1` gave them: on a block of conditions (`n ≤ p_j`) exactly on pivot
/// rows, the other rows' residuals the conditions; on a block measured
/// (`n = p_j + 1`) by least squares, the residual the error, what no
/// processor removes once the larger terms (fewer `ε`) have been removed.
/// Every `εhⁿ` term is the processor's (one Lyndon word per weight, one
/// column): the kernel's conditions start at `ε²`. The weight-2 block is
/// the column `A`, whose image `[A, B]` has one `B`.
pub fn eliminate_near(
    reach: Reach,
    l: &Series,
    nvars: usize,
    want_conjugator: bool,
) -> Result<Elimination, EffectiveError> {
    let letters = Letters::NearIntegrable(reach);
    let top = reach.top();
    let p = top - 1;
    let mut l = l.clone();
    l.retain(|w, _| letters.keeps(w));
    let mut conditions = Vec::new();
    let mut errors = Vec::new();
    let mut z_exp: Series =
        HashMap::from([(Vec::new(), Poly::constant(nvars, BigRational::one()))]);
    let y1 = letters.y1();
    for n in 2..=top {
        let rows = letters.lyndon_words(n);
        // A column with j letters B lands in rows with j and j + 1; it is
        // needed where its own rows (max(j, 1)) are kept.
        let cols: Vec<Word> = letters
            .below(n - 1)
            .into_iter()
            .filter(|u| n <= reach.of(b_count(u).max(1)))
            .collect();
        let basis: Vec<Series> = cols.iter().map(|u| basis_element(letters, u, 0)).collect();
        let images: Vec<Series> = basis
            .iter()
            .map(|b| bracket(letters, b, &y1, n, 0))
            .collect();
        let m: Vec<Vec<BigRational>> = rows
            .iter()
            .map(|w| {
                images
                    .iter()
                    .map(|s| s.get(w).map(constant).unwrap_or_else(BigRational::zero))
                    .collect()
            })
            .collect();
        let e: Vec<Poly> = rows
            .iter()
            .map(|w| l.get(w).cloned().unwrap_or_else(|| Poly::zero(nvars)))
            .collect();
        let mut c: Vec<Poly> = vec![Poly::zero(nvars); cols.len()];
        let jmax = rows.iter().map(|w| b_count(w)).max().unwrap_or(0);
        for j in 1..=jmax {
            let ri: Vec<usize> = (0..rows.len())
                .filter(|&i| b_count(&rows[i]) == j)
                .collect();
            let ci: Vec<usize> = (0..cols.len())
                .filter(|&k| b_count(&cols[k]).max(1) == j)
                .collect();
            // The rows' terms after the shift of the columns already fixed
            // (those with j − 1 letters B).
            let shifted: Vec<Poly> = ri
                .iter()
                .map(|&i| {
                    let mut r = e[i].clone();
                    for k in 0..cols.len() {
                        if !ci.contains(&k) && !m[i][k].is_zero() && !c[k].is_zero() {
                            r = r.sub(&c[k].scale(&m[i][k]));
                        }
                    }
                    r
                })
                .collect();
            let sub: Vec<Vec<BigRational>> = ri
                .iter()
                .map(|&i| ci.iter().map(|&k| m[i][k].clone()).collect())
                .collect();
            let imposed = n <= reach.degree(j);
            let cj = if ci.is_empty() {
                Vec::new()
            } else if imposed {
                let pivots = pivot_rows(&sub, ci.len()).ok_or_else(|| {
                    EffectiveError::Internal(format!(
                        "ad(A+B) is not injective on the terms with {j} letters B from weight {} to weight {n}",
                        n - 1
                    ))
                })?;
                solve_on_pivots(&sub, &shifted, &pivots, nvars)?
            } else {
                least_squares(&sub, &shifted, nvars)?
            };
            for (t, &k) in ci.iter().enumerate() {
                c[k] = cj[t].clone();
            }
            for (t, &i) in ri.iter().enumerate() {
                let r = residual(&sub[t], &shifted[t], &cj);
                let label = word_label(false, &rows[i]);
                if imposed {
                    push_condition(&mut conditions, label, n, r, want_conjugator, || {
                        reach.text()
                    })?;
                } else if !r.is_zero() {
                    errors.push(Term {
                        word: label,
                        weight: n,
                        poly: r,
                    });
                }
            }
        }
        clear(
            letters,
            &basis,
            &c,
            (n, top, p),
            nvars,
            &mut l,
            want_conjugator.then_some(&mut z_exp),
        );
    }
    Ok(Elimination {
        conditions,
        errors,
        conjugator: conjugator(letters, want_conjugator.then_some(&z_exp), p, nvars),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(v: i64) -> Poly {
        Poly::constant(0, BigRational::from_integer(v.into()))
    }

    #[test]
    fn exp_and_log_are_inverse() {
        let letters = Letters::Composition;
        let x: Series = HashMap::from([(vec![0], c(1)), (vec![1], c(2)), (vec![0, 1], c(3))]);
        let back = log(letters, &exp(letters, &x, 7, 0), 7, 0);
        assert_eq!(back, x);
    }

    #[test]
    fn the_conjugation_is_log_of_the_product() {
        // exp(ad_x) l = log(exp(x) exp(l) exp(−x)), in both alphabets.
        for (letters, top) in [(Letters::Composition, 9), (Letters::DriftKick, 6)] {
            let x: Series = HashMap::from([(vec![0, 1], c(2)), (vec![1, 0], c(-2))]);
            let l: Series = HashMap::from([(vec![0], c(1)), (vec![1], c(5))]);
            let direct = conjugate(letters, &x, &l, top, 0);
            let minus_x = scale(&x, &BigRational::from_integer((-1).into()));
            let product = mul(
                letters,
                &mul(
                    letters,
                    &exp(letters, &x, top, 0),
                    &exp(letters, &l, top, 0),
                    top,
                    0,
                ),
                &exp(letters, &minus_x, top, 0),
                top,
                0,
            );
            assert_eq!(direct, log(letters, &product, top, 0), "{letters:?}");
        }
    }

    #[test]
    fn the_image_of_ad_y1_is_injective_and_leaves_one_condition_per_odd_weight_up_to_five() {
        // Lyndon words of weight 5: Y₁Y₁Y₃ and Y₅; the image from weight 4
        // ([Y₁,Y₃]) is one-dimensional, so one condition remains (Y₅).
        let letters = Letters::Composition;
        assert_eq!(letters.lyndon_words(5).len(), 2);
        assert_eq!(letters.lyndon_words(4).len(), 1);
        assert_eq!(letters.lyndon_words(3).len(), 1);
        assert_eq!(letters.lyndon_words(2).len(), 0);
    }

    /// A symmetric drift–kick kernel's log with every odd-weight Lyndon
    /// coordinate up to weight 7 its own unknown: the conditions of
    /// effective order 6 are the coordinates outside the image of
    /// `ad_{A+B}`, 1 at weight 3 (of 2) and 3 at weight 5 (of 6), and the
    /// weight-7 error has 18 − 9 = 9 independent directions (Blanes, Casas
    /// & Ros 1999 count 1 + 3 against the classical 2 + 6).
    #[test]
    fn a_drift_kick_kernel_has_one_and_three_effective_conditions_at_weights_three_and_five() {
        let letters = Letters::DriftKick;
        let words: Vec<Word> = [3, 5, 7]
            .iter()
            .flat_map(|&n| letters.lyndon_words(n))
            .collect();
        assert_eq!(words.len(), 2 + 6 + 18);
        let nvars = words.len();
        let mut l: Series = HashMap::new();
        for (w, k) in letters.y1() {
            l.insert(w, Poly::constant(nvars, constant(&k)));
        }
        for (i, w) in words.iter().enumerate() {
            for (u, k) in basis_element(letters, w, nvars) {
                let term = Poly::var(nvars, i).scale(&constant(&k));
                let entry = l.entry(u).or_insert_with(|| Poly::zero(nvars));
                *entry = entry.add(&term);
            }
        }
        let elim = eliminate(letters, &l, 6, nvars, false).expect("eliminates");
        let at = |n: usize| elim.conditions.iter().filter(|t| t.weight == n).count();
        assert_eq!((at(3), at(5)), (1, 3));
        assert_eq!(elim.conditions.len(), 4);
        // The error is the projection of 18 coordinates on a 9-dimensional
        // complement: every coordinate may be nonzero, but they span 9.
        assert!(elim.errors.iter().all(|t| t.weight == 7));
        assert!(elim.errors.len() >= 9);
    }
}
