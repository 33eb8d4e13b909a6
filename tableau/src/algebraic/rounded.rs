//! A table with `root(...)` entries as a stepper needs it: its entries as
//! correctly rounded doubles, the exact zero pattern of `A`, and the order
//! its decided conditions prove. `butcher!` (compile time) and `symlab
//! compare --table` (run time) both step such a table from this one
//! function, so the two cannot round or classify it differently.

use super::alg::Alg;
use super::file::{AlgAnalysis, AlgFile};
use crate::analysis::Class;
use crate::rounding::F64Table;

/// The doubles of a root table and the facts that choose its step code.
#[derive(Clone, Debug, PartialEq)]
pub struct RootF64 {
    /// `a`, `b`, `c` (for a pair, the table acting on `q`), each entry the
    /// correctly rounded double of the exact value; `c` absent in the file
    /// is the rounded exact row sum.
    pub table: F64Table,
    /// A pair's `p` table (`a_hat`, `b_hat`, `c_hat`).
    pub hat: Option<F64Table>,
    /// The structure of `A` by exact zero tests (an entry whose zero test is
    /// beyond the budget counts as nonzero); a pair is stepped with all
    /// stages together, [`Class::Implicit`].
    pub class: Class,
    /// The order the decided conditions prove: 1 when `Σbᵢ = 1`, 2 when also
    /// `Σbᵢcᵢ = 1/2` with `c` the row sums; a pair's coupling conditions are
    /// not decided, so at most 1. Higher orders are not decided for such
    /// tables.
    pub order: usize,
}

/// Round `f`'s entries (an entry that cannot be rounded within the budget
/// is an error naming its field: `a[0][1]: cannot be rounded …`) and decide
/// its structure; `an` is `f.analyse()`.
pub fn round_root_table(f: &AlgFile, an: &AlgAnalysis) -> Result<RootF64, String> {
    let field = &f.field;
    let s = f.b.len();
    let zero = |x: &Alg| field.is_zero(x) == Ok(true);
    let round = |x: &Alg, what: String| {
        field
            .to_f64(x)
            .map_err(|e| format!("{what}: cannot be rounded to f64 within the budget ({e:?})"))
    };
    let table = |a: &[Vec<Alg>], b: &[Alg], c: Option<&Vec<Alg>>, names: [&str; 3]| {
        let mut af = vec![vec![0.0; s]; s];
        for i in 0..s {
            for j in 0..s {
                af[i][j] = round(&a[i][j], format!("{}[{i}][{j}]", names[0]))?;
            }
        }
        let bf = (0..s)
            .map(|i| round(&b[i], format!("{}[{i}]", names[1])))
            .collect::<Result<Vec<f64>, String>>()?;
        let cf = (0..s)
            .map(|i| match c {
                Some(c) => round(&c[i], format!("{}[{i}]", names[2])),
                None => {
                    let sum = a[i].iter().fold(Alg::zero(), |acc, x| acc.add(x));
                    round(&sum, format!("the row sum of {}[{i}]", names[0]))
                }
            })
            .collect::<Result<Vec<f64>, String>>()?;
        Ok::<F64Table, String>(F64Table {
            a: af,
            b: bf,
            c: cf,
        })
    };
    let q = table(&f.a, &f.b, f.c.as_ref(), ["a", "b", "c"])?;
    let hat = match (&f.a_hat, &f.b_hat) {
        (Some(ah), Some(bh)) => Some(table(
            ah,
            bh,
            f.c_hat.as_ref(),
            ["a_hat", "b_hat", "c_hat"],
        )?),
        _ => None,
    };
    // A pair is not tested: it steps with all stages together.
    let lower_triangular = || (0..s).all(|i| (i + 1..s).all(|j| zero(&f.a[i][j])));
    let class = if hat.is_some() || !lower_triangular() {
        Class::Implicit
    } else if (0..s).all(|i| zero(&f.a[i][i])) {
        Class::Explicit
    } else if (0..s).all(|i| !zero(&f.a[i][i]) && zero(&f.a[i][i].sub(&f.a[0][0]))) {
        Class::Sdirk
    } else {
        Class::Dirk
    };
    let holds = an.b_levels.iter().take_while(|v| **v == Some(true)).count();
    let order = if an.row_sums_ok == Some(true) && hat.is_none() {
        holds.min(2)
    } else {
        holds.min(1)
    };
    Ok(RootF64 {
        table: q,
        hat,
        class,
        order,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebraic::file::{Loaded, parse};

    fn rounded(body: &str) -> RootF64 {
        let text = format!("name = \"t\"\n{body}\n[let]\ng = \"root(x^2 - 2, 1, 2)\"\n");
        let Ok(Loaded::Algebraic(f)) = parse("test", &text) else {
            panic!("not read as a root table: {text}");
        };
        round_root_table(&f, &f.analyse()).expect("rounds")
    }

    #[test]
    fn explicit_and_sdirk_tables_are_told_apart_exactly() {
        // Explicit, order 2: Σbᵢcᵢ = (g/2)² = 1/2.
        let e = rounded("a = [[\"0\", \"0\"], [\"g/2\", \"0\"]]\nb = [\"1 - g/2\", \"g/2\"]");
        assert_eq!(e.class, Class::Explicit);
        assert_eq!(e.order, 2);
        assert_eq!(e.table.a[1][0], std::f64::consts::SQRT_2 / 2.0);
        assert_eq!(e.table.c, vec![0.0, std::f64::consts::SQRT_2 / 2.0]);
        assert!(e.hat.is_none());
        // The L-stable SDIRK with γ = 1 − √2/2: one diagonal value, order 2.
        let s = rounded(
            "a = [[\"1 - g/2\", \"0\"], [\"g/2\", \"1 - g/2\"]]\nb = [\"g/2\", \"1 - g/2\"]",
        );
        assert_eq!(s.class, Class::Sdirk);
        assert_eq!(s.order, 2);
        assert_eq!(s.table.c[1], 1.0);
    }
}
