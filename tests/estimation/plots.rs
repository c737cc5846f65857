//! Figures and the HTML report (feature `plot`): every figure is well-formed SVG, holds the
//! series it should for two and three degrees of freedom, the report shows and links every
//! figure, stored once, and its size does not grow with the records' length or lines.
#![cfg(feature = "plot")]

use bearing_ident::plot::{self, FigureOptions, ReportOptions};
use bearing_ident::quality::ImpactChecks;
use bearing_ident::simulate::{AntiAlias, Impact, ImpactTest, Simulator, seed_rig};
use bearing_ident::spectra::{ForceGate, Segmentation};
use bearing_ident::{
    Coefficients, Error, Estimator, Identification, Identifier, Method, Record, Window,
};
use faer::mat;

/// The seed's rig, two noisy hits per direction.
fn two_dof() -> (Vec<Record>, Identification) {
    let records = ImpactTest {
        per_direction: 2,
        noise: 0.05,
        ..ImpactTest::seed_rig()
    }
    .run(&seed_rig())
    .unwrap();
    let id = Identifier::new(8.0, 49.0).identify(&records).unwrap();
    (records, id)
}

/// A cross-coupled 3-DOF system (as in `recovery.rs`), two noisy hits per direction.
fn three_dof() -> (Vec<Record>, Identification) {
    let truth = Coefficients::new(
        mat![[2.0, 0.1, 0.0], [0.1, 2.5, 0.2], [0.0, 0.2, 3.0]],
        mat![[60.0, 8.0, -3.0], [-5.0, 70.0, 4.0], [2.0, -6.0, 80.0]],
        mat![
            [4.0e4, 6.0e3, -1.0e3],
            [2.0e3, 6.0e4, 5.0e3],
            [-2.0e3, 1.0e3, 9.0e4]
        ],
    )
    .unwrap();
    let records = ImpactTest {
        per_direction: 2,
        sample_rate: 2000.0,
        duration_s: 2.0,
        pulse_s: 0.003,
        noise: 0.02,
        ..ImpactTest::seed_rig()
    }
    .run(&truth)
    .unwrap();
    let id = Identifier::new(3.0, 60.0).identify(&records).unwrap();
    (records, id)
}

/// Parses `svg` and returns the names of its series groups; every group must draw something
/// besides its title.
fn series(svg: &str) -> Vec<String> {
    let doc = roxmltree::Document::parse(svg).expect("well-formed SVG");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    assert!(root.attribute("width").is_some() && root.attribute("viewBox").is_some());
    root.descendants()
        .filter(|n| n.tag_name().name() == "g" && n.attribute("class") == Some("series"))
        .map(|g| {
            let name = g
                .attribute("data-series")
                .expect("named series")
                .to_string();
            let drawn = g.children().filter(|c| c.is_element()).any(|c| {
                matches!(
                    c.tag_name().name(),
                    "polyline" | "circle" | "line" | "rect" | "polygon" | "text"
                )
            });
            assert!(drawn, "series `{name}` draws nothing");
            name
        })
        .collect()
}

/// Asserts that each of `names` is a series of `found`.
fn has_all(found: &[String], names: &[String]) {
    for name in names {
        assert!(found.contains(name), "no series `{name}` in {found:?}");
    }
}

fn elements(n: usize) -> Vec<String> {
    let axes = ["x", "y", "z"];
    (0..n * n)
        .map(|p| format!("{}{}", axes[p / n], axes[p % n]))
        .collect()
}

#[test]
fn matrix_figures_hold_four_series_per_element() {
    let opts = FigureOptions::default();
    for (n, (_, id)) in [(2, two_dof()), (3, three_dof())] {
        let flex = series(&plot::flexibility(&id, &opts).unwrap());
        let imp = series(&plot::impedance(&id, &opts).unwrap());
        let pf = series(&plot::per_frequency(&id, &opts).unwrap());
        for found in [&flex, &imp, &pf] {
            assert_eq!(found.len(), 4 * n * n, "n = {n}: {found:?}");
        }
        for el in elements(n) {
            has_all(
                &flex,
                &[
                    format!("|G {el}| measured"),
                    format!("|G {el}| model"),
                    format!("∠G {el} measured"),
                    format!("∠G {el} model"),
                ],
            );
            has_all(
                &imp,
                &[
                    format!("Re H {el} measured"),
                    format!("Re H {el} model K − ω²M"),
                    format!("Im H {el} measured"),
                    format!("Im H {el} model ωC"),
                ],
            );
            has_all(
                &pf,
                &[
                    format!("K {el}(ω)"),
                    format!("K {el} fit"),
                    format!("C {el}(ω)"),
                    format!("C {el} fit"),
                ],
            );
        }
    }
}

#[test]
fn impedance_has_error_bars_when_the_frf_has_a_variance() {
    let (_, id) = two_dof();
    assert!(id.frf().impedance_variance(0).is_some());
    let svg = plot::impedance(&id, &FigureOptions::default()).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let measured = doc
        .descendants()
        .find(|n| n.attribute("data-series") == Some("Re H xx measured"))
        .unwrap();
    // ErrorBar draws a vertical line and two caps per line.
    let lines = measured
        .children()
        .filter(|c| c.tag_name().name() == "line")
        .count();
    assert_eq!(lines, 3 * id.freqs_hz().len());
    assert!(svg.contains("Re H (kN/m)") && svg.contains("Im H (kN/m)"));
}

#[test]
fn coherence_figure_holds_outputs_conditioning_and_limits() {
    for (n, (_, id)) in [(2, two_dof()), (3, three_dof())] {
        let found = series(&plot::coherence(&id, &FigureOptions::default()).unwrap());
        let with_coherence = id.frf().multiple_coherence(0).is_some();
        let dropped = usize::from(!id.frf().dropped_hz().is_empty());
        let outputs = if with_coherence { n } else { 0 };
        // Band shading on both plots, condition numbers, two limits.
        assert_eq!(found.len(), outputs + 2 + 1 + 2 + dropped, "{found:?}");
        has_all(
            &found,
            &[
                "condition number".into(),
                "warn limit".into(),
                "refuse limit".into(),
            ],
        );
        if with_coherence {
            has_all(&found, &["coherence x".into(), "coherence y".into()]);
        }
    }
}

#[test]
fn convergence_has_three_blocks_or_says_why_not() {
    let (records, id) = two_dof();
    let svg = plot::convergence(&id, &FigureOptions::default()).unwrap();
    let found = series(&svg);
    // The history is the run's: one entry per iteration, the stopping rule (largest block
    // change at most the default tolerance 1e-8) met by the last entry only.
    let history = id.history();
    assert!(id.converged());
    assert!(history.len() >= 2, "{history:?}");
    assert_eq!(history.len(), id.iterations());
    let (last, before) = history.split_last().unwrap();
    assert!(last.change() <= 1e-8, "{last:?}");
    assert!(before.iter().all(|i| i.change() > 1e-8), "{history:?}");
    assert!(svg.contains(&format!("({} iterations)", history.len())));
    assert_eq!(
        found,
        ["mass change", "damping change", "stiffness change"].map(String::from)
    );
    let ls = Identifier::new(8.0, 49.0)
        .method(Method::LeastSquares)
        .identify(&records)
        .unwrap();
    let svg = plot::convergence(&ls, &FigureOptions::default()).unwrap();
    assert!(series(&svg).is_empty());
    assert!(svg.contains("method ls does not iterate"));
}

#[test]
fn record_figure_marks_impacts_gate_window_and_issues() {
    for (n, (records, _)) in [(2, two_dof()), (3, three_dof())] {
        let svg = plot::records(&records, None, None, &FigureOptions::default()).unwrap();
        let found = series(&svg);
        assert_eq!(found.len(), records.len() * (2 * n + 1), "{found:?}");
        let label = records[0].label();
        has_all(
            &found,
            &[
                format!("{label} force x"),
                format!("{label} displacement y"),
                format!("{label} impact"),
            ],
        );
    }
    // A force gate and an exponential window over whole records add one and two series per
    // record.
    let (records, _) = two_dof();
    let id = Identifier::new(8.0, 49.0)
        .force_gate(ForceGate::new(0.05, 0.01).unwrap())
        .window(Window::exponential_to(0.05, 1.2))
        .identify(&records)
        .unwrap();
    let found =
        series(&plot::records(&records, Some(&id), None, &FigureOptions::default()).unwrap());
    assert_eq!(found.len(), records.len() * (2 * 2 + 1 + 1 + 2));
    assert!(found.contains(&format!("{} force gate", records[0].label())));
    // A bounce 30 ms after the hit is marked as a double hit.
    let mut sim = Simulator::new(&seed_rig(), 6700.0, 8040, AntiAlias::default()).unwrap();
    let hit = |peak_n: f64, start_s: f64| Impact {
        direction: vec![1.0, 0.0],
        peak_n,
        duration_s: 0.002,
        start_s,
    };
    let bounce = sim
        .record("bounce", &[hit(500.0, 0.02), hit(150.0, 0.05)])
        .unwrap();
    let svg = plot::records(
        &[bounce],
        None,
        Some(&ImpactChecks::default()),
        &FigureOptions::default(),
    )
    .unwrap();
    assert!(series(&svg).contains(&"bounce double hit".to_string()));
    assert!(svg.contains("double hit (0.30 × peak)"));
}

#[test]
fn record_figure_needs_records() {
    let e = plot::records(&[], None, None, &FigureOptions::default()).unwrap_err();
    assert_eq!(e, Error::NoRecords);
}

#[test]
fn axis_names_label_the_elements() {
    let (_, id) = two_dof();
    let opts = FigureOptions {
        axes: vec!["u".into(), "v".into()],
        ..FigureOptions::default()
    };
    let found = series(&plot::flexibility(&id, &opts).unwrap());
    assert!(found.contains(&"|G uv| model".to_string()));
}

#[test]
fn report_shows_and_links_every_figure() {
    let (records, id) = two_dof();
    let dir = tempfile::tempdir().unwrap();
    let options = ReportOptions {
        title: "Rig <A> & B".into(),
        context: vec!["4 records".into()],
        text: Some("coefficient table".into()),
        truth: Some(seed_rig()),
        ..ReportOptions::default()
    };
    let written = plot::report(&id, &records, dir.path(), &options).unwrap();
    let stems = [
        "flexibility",
        "impedance",
        "coherence",
        "per_frequency",
        "records",
        "convergence",
        "residual",
    ];
    assert_eq!(written.len(), stems.len() + 1);
    assert_eq!(written.last().unwrap(), &dir.path().join("index.html"));
    let html = std::fs::read_to_string(dir.path().join("index.html")).unwrap();
    for stem in stems {
        let file = dir.path().join(format!("{stem}.svg"));
        let svg = std::fs::read_to_string(&file).unwrap();
        assert!(!series(&svg).is_empty() || stem == "convergence");
        assert!(
            html.contains(&format!("href=\"{stem}.svg\"")),
            "{stem} not linked"
        );
        assert!(
            html.contains(&format!("id=\"fig-{stem}\"")),
            "{stem} no anchor"
        );
        // Shown from its file, not embedded a second time.
        assert!(
            html.contains(&format!("<img src=\"{stem}.svg\"")),
            "{stem} not shown"
        );
    }
    assert!(!html.contains("<svg"));
    // Static: no scripts, nothing fetched from elsewhere.
    assert!(!html.contains("<script") && !html.contains("src=\"http"));
    assert!(!html.contains("<link"));
    // The table, escaped title, truth columns and the folded text report.
    assert!(html.contains("<title>Rig &lt;A&gt; &amp; B</title>"));
    assert!(html.contains("<td>K_xx (N/m)</td>") && html.contains("<th>true</th>"));
    // The error bars' captions say what stands behind them: two paired sets.
    assert!(html.contains("Each error bar is the scatter of the 2 paired sets at its line."));
    assert!(html.contains("<pre>coefficient table</pre>"));
}

/// A report's files are bounded whatever the records' length and the number of lines:
/// four random records of 300 s with Welch segments of 128 s give over 5000 lines (each
/// figure of the impedance and per-frequency kind was 30 MB drawn point by point); every
/// SVG stays under 1 MB and the page under 2 MB.
#[test]
fn report_size_is_bounded_for_long_records_with_many_lines() {
    let (rate, len) = (256.0, 76_800);
    let mut sim = Simulator::new(&seed_rig(), rate, len, AntiAlias::default()).unwrap();
    let records: Vec<Record> = (0..4)
        .map(|k| {
            sim.random_record(format!("random-{k}"), 20.0, 7 + k)
                .unwrap()
        })
        .collect();
    let id = Identifier::new(8.0, 49.0)
        .estimator(Estimator::H1)
        .segmentation(Segmentation::Welch { len: 32_768 })
        .window(Window::Hann)
        .identify(&records)
        .unwrap();
    assert!(id.freqs_hz().len() > 5000, "{} lines", id.freqs_hz().len());
    let dir = tempfile::tempdir().unwrap();
    let options = ReportOptions {
        checks: None,
        ..ReportOptions::default()
    };
    let written = plot::report(&id, &records, dir.path(), &options).unwrap();
    assert_eq!(written.len(), 8);
    for path in &written {
        let size = std::fs::metadata(path).unwrap().len();
        let limit = if path.ends_with("index.html") {
            2_000_000
        } else {
            1_000_000
        };
        assert!(size <= limit, "{}: {size} bytes", path.display());
        if path.extension().is_some_and(|e| e == "svg") {
            let svg = std::fs::read_to_string(path).unwrap();
            assert!(!series(&svg).is_empty() || path.ends_with("convergence.svg"));
        }
    }
    // Dense lines are drawn as lines over the band of their error bars, not point by point.
    let impedance = std::fs::read_to_string(dir.path().join("impedance.svg")).unwrap();
    assert!(impedance.matches("<circle").count() < 100);
    assert!(impedance.contains("<polygon"));
}

#[test]
fn report_into_a_file_path_is_an_io_error() {
    let (records, id) = two_dof();
    let file = tempfile::NamedTempFile::new().unwrap();
    let e = plot::report(&id, &records, file.path(), &ReportOptions::default()).unwrap_err();
    assert_eq!(e.kind(), "io_error");
}
