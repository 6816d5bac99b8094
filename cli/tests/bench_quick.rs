//! `hairsys bench --quick` through the real binary: it finishes, and writes both charts as PNG
//! files and a table with a row for every case and method.

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
    for png in ["pareto.png", "stability_map.png"] {
        let bytes = std::fs::read(dir.join("out").join(png)).unwrap();
        assert!(bytes.starts_with(PNG_SIGNATURE), "{png} is not a PNG");
        assert!(bytes.len() > 10_000, "{png} is nearly empty");
    }
    let table = std::fs::read_to_string(dir.join("out/bench.md")).unwrap();
    let runs_section = table
        .split("## Runs")
        .nth(1)
        .and_then(|rest| rest.split("## Stability").next())
        .expect("the table has a Runs section before the Stability one");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/bench.json")).unwrap())
            .unwrap();
    let methods = [
        "explicit Euler",
        "semi-implicit Euler",
        "semi-implicit Euler, no damping loop",
        "semi-implicit Euler + projection",
        "semi-implicit Euler + projection, no stretch springs",
    ];
    let ladder = 9; // 1, 2, 4 … 256 substeps per frame
    for case in ["pendulum", "chain", "cantilever", "head"] {
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
    let runs = json["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 4 * (methods.len() * ladder + 1));
    assert!(
        table.contains("counts as **converged** when halving its step"),
        "the table must say what converged means"
    );
    assert!(table.contains("## Stability"), "no stability table");
}
