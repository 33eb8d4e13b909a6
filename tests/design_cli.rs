//! End-to-end tests of `symlab design`: a family file in, tables and a
//! report out, and the tables pass `symlab check`.

use crate::common::symlab;

fn out_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("symlab-design-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// `symlab ARGS` exits with status 2 and a message containing `needle`.
fn refused(args: &[&str], needle: &str) {
    let (code, out, err) = symlab(args);
    assert_eq!(code, 2, "{args:?}: {out}");
    assert!(err.contains(needle), "{args:?}: {err}");
}

#[test]
fn design_writes_tables_that_check_accepts() {
    let dir = out_dir("sb3a");
    let d = dir.to_str().unwrap();
    let (code, out, err) = symlab(&[
        "design",
        "designs/mclachlan-sb3a.toml",
        "--out",
        d,
        "--starts",
        "40",
    ]);
    assert_eq!(code, 0, "stderr: {err}");
    assert!(out.contains("certified, radius"), "{out}");
    let table = dir.join("mclachlan-sb3a-order-4-1.toml");
    assert!(dir.join("report.md").exists());
    let (code, out, err) = symlab(&["check", "--json", table.to_str().unwrap()]);
    assert_eq!(code, 0, "stderr: {err}\n{out}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    // The exact order of the printed decimals is 2 on separable systems
    // (their degree-3 residuals are about 1e-51, not 0); the certified claim
    // holds: `check` re-proves the certificate (order 4 within the radius of
    // the printed coefficients).
    assert_eq!(v["order_separable"], 2, "{v}");
    let claims = v["claims"].as_array().unwrap();
    assert_eq!(claims.len(), 3, "{v}");
    assert!(claims.iter().all(|c| c["holds"] == true), "{v}");
    assert_eq!(claims[2]["claim"], "order = 4 (certified)");
    assert_eq!(v["certificate"]["radius"], "1e-46", "{v}");
    assert_eq!(
        v["certificate"]["unknowns"],
        serde_json::json!(["a1", "a2"]),
        "{v}"
    );
    let (_, text, _) = symlab(&["check", table.to_str().unwrap()]);
    assert!(
        text.contains(
            "certificate  order 4 within radius 1e-46 of the printed coefficients (a1, a2)"
        ),
        "{text}"
    );
    // The emitted table is a method like any other: `compare --table` runs
    // it with its certified order as its order.
    let out = dir.join("cmp");
    let (code, stdout, err) = symlab(&[
        "compare",
        "--problem",
        "kepler",
        "--methods",
        "forest-ruth",
        "--table",
        table.to_str().unwrap(),
        "--points",
        "2",
        "--repeats",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "stderr: {err}\n{stdout}");
    let csv = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let (method, order) = (
        header.iter().position(|h| *h == "method").unwrap(),
        header.iter().position(|h| *h == "order").unwrap(),
    );
    let mine: Vec<Vec<&str>> = lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|r| r[method] == "mclachlan-sb3a-order-4-1")
        .collect();
    assert!(!mine.is_empty(), "{csv}");
    assert!(mine.iter().all(|r| r[order] == "4"), "{csv}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_bad_family_is_an_error_naming_file_and_field() {
    let (code, _, err) = symlab(&["design", "tests/main.rs", "--out", "/nonexistent"]);
    assert_eq!(code, 2);
    assert!(err.contains("tests/main.rs: not a TOML file"), "{err}");
    let (code, _, err) = symlab(&[
        "design",
        "designs/yoshida4.toml",
        "--out",
        "/tmp",
        "--starts",
        "0",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("designs/yoshida4.toml: field starts"), "{err}");
}

/// `--compare PROBLEM`: the best designs run beside library methods in one
/// work–precision sweep, its report written into DIR/compare/.
#[test]
fn design_compare_runs_designs_beside_the_library() {
    let dir = out_dir("compare");
    let d = dir.to_str().unwrap();
    let (code, out, err) = symlab(&[
        "design",
        "designs/mclachlan-sb3a.toml",
        "--out",
        d,
        "--starts",
        "40",
        "--compare",
        "kepler",
        "--methods",
        "forest-ruth",
        "--designs",
        "2",
        "--points",
        "2",
        "--repeats",
        "1",
    ]);
    assert_eq!(code, 0, "stderr: {err}\n{out}");
    let cmp = dir.join("compare");
    assert!(cmp.join("report.md").exists(), "{out}");
    // The evaluations each method needs to reach an error, designs marked.
    let table = std::fs::read_to_string(cmp.join("designs.md")).unwrap();
    assert!(
        table.contains("| mclachlan-sb3a-order-4-1 | yes |"),
        "{table}"
    );
    assert!(table.contains("| forest-ruth |  |"), "{table}");
    let csv = std::fs::read_to_string(cmp.join("runs.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let method = header.iter().position(|h| *h == "method").unwrap();
    let mut ids: Vec<String> = lines
        .map(|l| l.split(',').nth(method).unwrap().to_string())
        .collect();
    ids.dedup();
    assert_eq!(
        ids,
        [
            "forest-ruth",
            "mclachlan-sb3a-order-4-1",
            "mclachlan-sb3a-order-4-2"
        ],
        "{csv}"
    );
    let _ = std::fs::remove_dir_all(&dir);
    // Without a proven design or with a bad problem: errors that say so.
    refused(
        &[
            "design",
            "designs/yoshida4.toml",
            "--out",
            d,
            "--compare",
            "nope",
        ],
        "the built-in problems are",
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--compare outer-solar --wisdom-holman`: the designs run on the
/// Wisdom–Holman split as `wh:` rows (Kepler drifts, interaction kicks),
/// stepped as the library's `wh:` methods are, so designs.md compares
/// their wall times too; the sweep's flags belong to --compare.
#[test]
fn design_compare_on_the_wisdom_holman_split() {
    let dir = out_dir("wh");
    let d = dir.to_str().unwrap();
    let (code, out, err) = symlab(&[
        "design",
        "designs/saba2.toml",
        "--out",
        d,
        "--compare",
        "outer-solar",
        "--wisdom-holman",
        "--methods",
        "wh:leapfrog",
        "--designs",
        "1",
        "--t-end",
        "20000",
        "--points",
        "2",
        "--repeats",
        "1",
    ]);
    assert_eq!(code, 0, "stderr: {err}\n{out}");
    let cmp = dir.join("compare");
    let csv = std::fs::read_to_string(cmp.join("runs.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (method, evals, steps) = (col("method"), col("evals"), col("steps"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let design = "wh:saba2-generalised-order-4-2-1";
    let mine: Vec<&Vec<&str>> = rows.iter().filter(|r| r[method] == design).collect();
    assert_eq!(mine.len(), 2, "{csv}");
    // SABA2: two interaction kicks a step (the drifts are Kepler flows).
    for r in &mine {
        let (e, n): (u64, u64) = (r[evals].parse().unwrap(), r[steps].parse().unwrap());
        assert_eq!(e, 2 * n, "{csv}");
    }
    let table = std::fs::read_to_string(cmp.join("designs.md")).unwrap();
    assert!(table.contains(&format!("| {design} | yes |")), "{table}");
    assert!(table.contains("| wh:leapfrog |  |"), "{table}");
    assert!(table.contains("Wall time, ms"), "{table}");
    assert!(table.contains("| wh:leapfrog |  | generated |"), "{table}");
    let _ = std::fs::remove_dir_all(&dir);

    // A problem without the split, and a sweep flag without --compare.
    refused(
        &[
            "design",
            "designs/saba2.toml",
            "--out",
            d,
            "--compare",
            "kepler",
            "--wisdom-holman",
            "--points",
            "2",
        ],
        "kepler has none",
    );
    refused(
        &["design", "designs/saba2.toml", "--out", d, "--points", "2"],
        "--points belongs to --compare",
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The second-corrector family (`designs/whckl-c17-corrector2.toml`): an
/// exact design with no search (its search flags refused), its table run
/// beside WHCKL c17 on the Wisdom–Holman split of the outer solar system in
/// one sweep, at the same step sizes.
#[test]
fn design_second_corrector_runs_beside_whckl() {
    let dir = out_dir("corrector2");
    let d = dir.to_str().unwrap();
    let (code, out, err) = symlab(&[
        "design",
        "designs/whckl-c17-corrector2.toml",
        "--out",
        d,
        "--compare",
        "outer-solar",
        "--wisdom-holman",
        "--methods",
        "wh:whckl-c17",
        "--t-end",
        "20000",
        "--h-min",
        "100",
        "--h-max",
        "400",
        "--points",
        "2",
        "--repeats",
        "1",
    ]);
    assert_eq!(code, 0, "stderr: {err}\n{out}");
    assert!(out.contains("c² = 11/5760 exactly"), "{out}");
    assert!(dir.join("report.md").exists(), "{out}");
    let csv = std::fs::read_to_string(dir.join("compare").join("runs.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (method, steps, error) = (col("method"), col("steps"), col("error"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let of = |m: &str| -> Vec<(u64, f64)> {
        rows.iter()
            .filter(|r| r[method] == m)
            .map(|r| (r[steps].parse().unwrap(), r[error].parse().unwrap()))
            .collect()
    };
    let library = of("wh:whckl-c17");
    let design = of("wh:whckl-c17-with-a-second-corrector");
    assert_eq!(library.len(), 2, "{csv}");
    assert_eq!(design.len(), 2, "{csv}");
    for ((nl, _), (nd, ed)) in library.iter().zip(&design) {
        assert_eq!(nl, nd, "{csv}");
        assert!(ed.is_finite() && *ed < 1e-3, "{csv}");
    }
    let table = std::fs::read_to_string(dir.join("compare").join("designs.md")).unwrap();
    assert!(
        table.contains("| wh:whckl-c17-with-a-second-corrector | yes |"),
        "{table}"
    );
    refused(
        &[
            "design",
            "designs/whckl-c17-corrector2.toml",
            "--out",
            d,
            "--starts",
            "5",
        ],
        "--starts",
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--rank-steps N`: the proven designs ranked by their error on the
/// problem after N steps (printed, smallest first), and the first of that
/// ranking is the one compared; N = 0 and the flag without --compare are
/// refused by name.
#[test]
fn design_rank_steps_ranks_by_the_error_on_the_problem() {
    let dir = out_dir("rank-steps");
    let d = dir.to_str().unwrap();
    let (code, out, err) = symlab(&[
        "design",
        "designs/rkn6-aba8.toml",
        "--out",
        d,
        "--starts",
        "300",
        "--compare",
        "pendulum",
        "--rank-steps",
        "300",
        "--designs",
        "1",
        "--methods",
        "blanes-moan-prk10",
        "--points",
        "3",
        "--repeats",
        "1",
    ]);
    assert_eq!(code, 0, "stderr: {err}\n{out}");
    let ranking: Vec<(String, f64)> = out
        .lines()
        .skip_while(|l| !l.starts_with("ranked by the error on pendulum after 300 steps"))
        .skip(1)
        .map_while(|l| {
            let (name, e) = l.trim().split_once(". ")?.1.split_once(": ")?;
            Some((name.to_string(), e.parse().ok()?))
        })
        .collect();
    assert!(ranking.len() >= 2, "{out}");
    assert!(ranking.windows(2).all(|w| w[0].1 <= w[1].1), "{ranking:?}");
    let table = std::fs::read_to_string(dir.join("compare").join("designs.md")).unwrap();
    assert!(
        table.contains(&format!("| {} | yes |", ranking[0].0)),
        "{table}"
    );
    for (name, _) in &ranking[1..] {
        assert!(!table.contains(&format!("| {name} | yes |")), "{table}");
    }
    let _ = std::fs::remove_dir_all(&dir);
    refused(
        &[
            "design",
            "designs/rkn6-aba8.toml",
            "--out",
            d,
            "--compare",
            "pendulum",
            "--rank-steps",
            "0",
        ],
        "--rank-steps",
    );
    refused(
        &[
            "design",
            "designs/rkn6-aba8.toml",
            "--out",
            d,
            "--rank-steps",
            "10",
        ],
        "--rank-steps",
    );
}

/// A family file is read up to a limit: `/dev/zero` is refused by name,
/// quickly, never read until memory runs out.
#[test]
#[cfg_attr(not(unix), ignore = "reads /dev/zero, which only Unix has")]
fn an_endless_family_file_is_read_up_to_a_limit() {
    let start = std::time::Instant::now();
    let (code, _, err) = symlab(&["design", "/dev/zero", "--out", "/tmp/symlab-design-zero"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("/dev/zero") && err.contains("larger than 1048576 bytes"),
        "{err}"
    );
    assert!(start.elapsed().as_secs() < 10, "{:?}", start.elapsed());
}

/// A processed kernel (`processed = true`): the processed table (kernel and
/// processor) is written, `symlab check` accepts its effective-order claim,
/// and `compare --table` steps it with its processor (the error falls as
/// h⁶ on Kepler).
#[test]
fn design_writes_a_processed_table_that_check_and_compare_accept() {
    let dir = out_dir("processed");
    let d = dir.to_str().unwrap();
    let (code, out, err) = symlab(&[
        "design",
        "designs/bcm-processed6-s11.toml",
        "--out",
        d,
        "--starts",
        "50",
    ]);
    assert_eq!(code, 0, "stderr: {err}");
    assert!(out.contains("certified, radius"), "{out}");
    let table = dir.join("processed-composition-11-stages-effective-order-6-1.toml");
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(
        report.contains("claims held: order = 6 (residual < 1e-40)"),
        "{report}"
    );
    let (code, out, err) = symlab(&["check", "--json", table.to_str().unwrap()]);
    assert_eq!(code, 0, "stderr: {err}\n{out}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let claims = v["claims"].as_array().unwrap();
    assert!(claims.iter().all(|c| c["holds"] == true), "{v}");
    assert!(
        claims
            .iter()
            .any(|c| c["claim"] == "order = 6 (residual < 1e-40)"),
        "{v}"
    );
    let cmp = dir.join("cmp");
    let (code, out, err) = symlab(&[
        "compare",
        "--problem",
        "kepler",
        "--table",
        table.to_str().unwrap(),
        "--methods",
        "interp:yoshida6",
        "--points",
        "4",
        "--h-max",
        "0.04",
        "--h-min",
        "0.005",
        "--repeats",
        "1",
        "--out",
        cmp.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "stderr: {err}\n{out}");
    let line = out
        .lines()
        .find(|l| l.starts_with("processed-composition-11"))
        .unwrap_or_else(|| panic!("{out}"));
    // The slope column (fifth): the effective order, 6, not the kernel's 2.
    let slope: f64 = line.split_whitespace().nth(4).unwrap().parse().unwrap();
    assert!((slope - 6.0).abs() < 0.3, "{line}");
    let _ = std::fs::remove_dir_all(&dir);
}
