//! Tests of `compare::plot` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::plot::*;
#[test]
fn draws_log_and_linear_plots_to_png_and_svg() {
    let dir = std::env::temp_dir().join(format!("symlab-plot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let series = [Series {
        name: "x²".into(),
        points: (1..20).map(|i| (i as f64, (i * i) as f64)).collect(),
        markers: true,
    }];
    for (file, log) in [("a.png", true), ("b.svg", false)] {
        let path = dir.join(file);
        let plot = Plot {
            title: "test",
            x_label: "x",
            y_label: "y",
            log_x: log,
            log_y: log,
            series: &series,
        };
        lines(&path, &plot).unwrap();
        assert!(std::fs::metadata(&path).unwrap().len() > 1000);
    }
    let empty = [Series {
        name: "none".into(),
        points: vec![(0.0, -1.0)],
        markers: false,
    }];
    let plot = Plot {
        title: "t",
        x_label: "x",
        y_label: "y",
        log_x: true,
        log_y: true,
        series: &empty,
    };
    assert!(lines(&dir.join("c.png"), &plot).is_err());
    assert!(lines(&dir.join("c.jpg"), &plot).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_captioned_bitmap_is_written_as_a_png_and_a_wrong_size_is_an_error() {
    let dir = std::env::temp_dir().join(format!("symlab-captioned-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("x.png");
    captioned_png(&path, (40, 30), vec![200; 40 * 30 * 3], "test").unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let e = captioned_png(&path, (40, 30), vec![0; 10], "test").unwrap_err();
    assert!(e.to_string().contains("wrong size"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
