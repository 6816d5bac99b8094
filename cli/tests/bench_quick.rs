//! `hairsys bench --quick` through the real binary: it finishes, and writes its charts as PNG
//! files and a table with a row for every case and method (the rod's projection iteration
//! counts and the strips included), the strips' cost per represented hair, the rod's
//! tip-moment table, where `hairsys plan` lands on the head case, the curl kept on the curly
//! case and the segments axis.

mod common;

use common::{hairsys, tempdir};

const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

#[test]
fn bench_quick_writes_pngs_and_a_table_row_per_case_and_method() {
    let dir = tempdir("bench-quick");
    let out = hairsys(&["bench", "--quick", "--out", "out", "--quiet"], &dir);
    assert!(
        out.status.success(),
        "bench failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stdout.is_empty(), "--quiet printed something");
    for png in ["pareto.png", "stability_map.png", "segments.png"] {
        let bytes = std::fs::read(dir.join("out").join(png)).unwrap();
        assert!(bytes.starts_with(PNG_SIGNATURE), "{png} is not a PNG");
        assert!(bytes.len() > 10_000, "{png} is nearly empty");
    }
    let table = std::fs::read_to_string(dir.join("out/bench.md")).unwrap();
    let runs_section = table
        .split("## Runs")
        .nth(1)
        .and_then(|rest| rest.split("\n## ").next())
        .expect("the table has a Runs section");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/bench.json")).unwrap())
            .unwrap();
    let methods = [
        "explicit Euler",
        "semi-implicit Euler",
        "semi-implicit Euler, no damping loop",
        "semi-implicit Euler + projection",
        "semi-implicit Euler + projection, no stretch springs",
        "implicit Euler",
        "implicit Euler, physical springs",
        "BDF2",
        "BDF2, physical springs",
        "XPBD",
        "XPBD, physical springs",
        "rod, 1 projection iteration",
        "rod, 2 projection iterations",
        "rod, 4 projection iterations",
        "rod, 8 projection iterations",
    ];
    let ladder = 9; // 1, 2, 4 … 256 substeps per frame
    let cases = [
        "pendulum",
        "chain",
        "chain-rest",
        "cantilever",
        "curly",
        "drape",
        "head",
    ];
    for case in cases {
        for m in methods {
            let rows = runs_section
                .lines()
                .filter(|l| l.starts_with(&format!("| {case} | {m} | ")))
                .count();
            // One row per substep count; the default method has the `auto` run too.
            let expected = ladder + usize::from(m == "semi-implicit Euler");
            assert_eq!(rows, expected, "rows of {case} / {m}");
        }
        assert!(
            runs_section.contains(&format!("| {case} | semi-implicit Euler | ")),
            "no row for {case}"
        );
        assert!(
            runs_section.lines().any(|l| l
                .starts_with(&format!("| {case} | semi-implicit Euler | "))
                && l.contains("(auto)")),
            "no auto row for {case}"
        );
    }
    // The strip case runs the strips and the default mass-spring method (the same edges) only.
    for m in ["strips", "semi-implicit Euler"] {
        let rows = runs_section
            .lines()
            .filter(|l| l.starts_with(&format!("| head-strips | {m} | ")))
            .count();
        assert_eq!(
            rows,
            ladder + usize::from(m == "semi-implicit Euler"),
            "rows of head-strips / {m}"
        );
    }
    let runs = json["runs"].as_array().unwrap();
    assert_eq!(
        runs.len(),
        cases.len() * (methods.len() * ladder + 1) + 2 * ladder + 1
    );
    // Every stable head-case run has a cost per represented hair; rod runs carry their
    // projection figures.
    for run in runs.iter().filter(|r| r["status"] == "stable") {
        let case = run["case"].as_str().unwrap();
        let method = run["method"].as_str().unwrap();
        let per_hair = run["cost"]["us_per_represented_hair"].as_f64();
        assert_eq!(
            per_hair.is_some(),
            case.starts_with("head"),
            "{case} / {method}: cost per represented hair {per_hair:?}"
        );
        assert_eq!(
            run["projection"].is_object(),
            method.starts_with("rod"),
            "{case} / {method}: projection figures"
        );
    }
    assert!(table.contains("## Strips: cost per represented hair"));
    let tip = table
        .split("## Rod: cantilever under a tip moment")
        .nth(1)
        .expect("the table has the rod's tip-moment section");
    assert!(
        tip.contains("| at rest |"),
        "no tip-moment run came to rest"
    );
    assert!(
        json["not_run"]
            .as_array()
            .unwrap()
            .iter()
            .any(|n| n["case"] == "head-strips" && n["method"] == "rod, 1 projection iteration"),
        "the report must say which cases a model cannot run"
    );
    assert!(
        table.contains("counts as **converged** when halving its substep (time) and halving its"),
        "the table must say what converged means"
    );
    // One truth per case, analytic where physics has an answer.
    let truths = json["truths"].as_array().unwrap();
    assert_eq!(truths.len(), cases.len() + 1);
    for t in truths {
        let name = t["truth"].as_str().unwrap();
        let analytic = matches!(
            t["case"].as_str(),
            Some("pendulum" | "chain" | "chain-rest")
        );
        assert_eq!(name.starts_with("analytic"), analytic, "{t}");
    }
    // Every stable run reports the measures beside position error.
    for run in runs.iter().filter(|r| r["status"] == "stable") {
        for key in ["tip_rms", "length_error", "position_rms"] {
            assert!(run["errors"][key].as_f64().is_some(), "{run}: {key}");
        }
    }
    assert!(table.contains("## Stability"), "no stability table");
    // Where `hairsys plan` lands on the head case: one point per tolerance, each choice run
    // against the head truth, the two choices different.
    let plan = json["plan"].as_array().unwrap();
    assert_eq!(plan.len(), 2, "{plan:?}");
    for p in plan {
        assert_eq!(p["case"], "head");
        assert!(p["truth_error"].as_f64().is_some_and(|e| e > 0.0), "{p}");
        assert!(p["ms_per_frame"].as_f64().is_some_and(|c| c > 0.0), "{p}");
        assert!(p["plan_error"].as_f64().unwrap() <= p["tolerance"].as_f64().unwrap());
    }
    assert_ne!(plan[0]["chosen"], plan[1]["chosen"], "{plan:?}");
    assert!(table.contains("## Where `hairsys plan` lands"));
    // The curly truth is curved: every stable run on it has its curl kept, a number.
    for run in runs
        .iter()
        .filter(|r| r["status"] == "stable" && r["case"] == "curly")
    {
        assert!(run["errors"]["curl_kept"].as_f64().is_some(), "{run}");
    }
    // The segments axis: every method that runs them on the three re-segmentable cases at 4, 8
    // and 16 segments, and a table section for it.
    let segments = json["segments"].as_array().unwrap();
    for case in ["cantilever", "curly", "drape"] {
        for n in [4, 8, 16] {
            let rows = segments
                .iter()
                .filter(|r| r["case"] == case && r["segments"] == n)
                .count();
            assert_eq!(rows, methods.len(), "{case} at {n} segments");
        }
    }
    assert_eq!(segments.len(), 3 * 3 * methods.len());
    assert!(table.contains("## Segments per strand"));
}
