//! `hairsys bench`: runs the `hairsys-bench` crate's cases with a progress bar and says where
//! its charts and tables went (or prints the report as JSON).

use std::path::PathBuf;

use hairsys_bench::{BenchOptions, Event};

use crate::error::CliError;
use crate::progress::Progress;

/// Arguments of `bench`.
#[derive(clap::Args)]
pub struct BenchArgs {
    /// Small cases and grids: about a minute and a quarter on 2 cores instead of ten minutes.
    #[arg(long)]
    quick: bool,
    /// Directory for pareto.png, stability_map.png, bench.md and bench.json.
    #[arg(long)]
    out: PathBuf,
    /// Print nothing but errors.
    #[arg(long, conflicts_with = "json")]
    quiet: bool,
    /// Print one JSON object per run and the report as JSON on stdout.
    #[arg(long)]
    json: bool,
}

/// The command's progress display behind the bench's [`hairsys_bench::Progress`]: the bar is
/// made when the bench says how many runs it will make.
struct BenchProgress {
    quiet: bool,
    json: bool,
    display: std::sync::OnceLock<Progress>,
}

impl hairsys_bench::Progress for BenchProgress {
    fn start(&self, total: u64) {
        let _ = self
            .display
            .set(Progress::new(total, self.quiet, self.json, "bench"));
    }

    fn tick(&self, event: &Event<'_>) {
        if let Some(p) = self.display.get() {
            p.tick(event);
        }
    }

    fn finish(&self) {
        if let Some(p) = self.display.get() {
            p.finish();
        }
    }
}

/// `bench`: runs the bench, then prints where its files went (or the report as JSON).
pub fn run(args: &BenchArgs) -> Result<(), CliError> {
    let progress = BenchProgress {
        quiet: args.quiet,
        json: args.json,
        display: std::sync::OnceLock::new(),
    };
    let opts = BenchOptions {
        quick: args.quick,
        out: args.out.clone(),
    };
    let report =
        hairsys_bench::run(&opts, &progress).map_err(|e| CliError::failed(e.to_string()))?;
    if args.json {
        outln!(
            "{}",
            serde_json::to_string(&report).expect("reports serialise")
        );
    } else if !args.quiet {
        outln!(
            "bench done in {:.0} s: {} in {}",
            report.seconds,
            hairsys_bench::report::FILES.join(", "),
            args.out.display()
        );
    }
    Ok(())
}
