//! Arguments several commands share: frame ranges, child overrides, cache compression, and the
//! kernel copy chosen by the environment.

use clap::ValueEnum;
use hair_cache::Compression;
use hair_core::KernelChoice;
use hair_render::ChildCount;
use hairsys::output::children::ChildOverrides;

use crate::error::CliError;

/// Child settings overriding the scene's `[children]` section (render-children export, cache
/// export --children).
#[derive(clap::Args)]
pub struct ChildArgs {
    /// Children per parent strand [scene [children] per_parent, else 10].
    #[arg(long, conflicts_with = "count")]
    pub children_per_parent: Option<u32>,
    /// Total number of children, spread over the parents [scene [children] count].
    #[arg(long)]
    count: Option<u64>,
    /// Simple (around one parent) or interpolated (between parents) children [scene, else simple].
    #[arg(long, value_enum)]
    mode: Option<ChildModeArg>,
    /// Parents blended per interpolated child, 1–8 [scene, else 4].
    #[arg(long)]
    neighbours: Option<u32>,
    /// Display level of detail (the scene's [children] display, else 10 % of the children with
    /// the parents' points) instead of render.
    #[arg(long)]
    pub display: bool,
    /// Radius of the disc children are rooted in around their parent's root, m [scene, else 0.005].
    #[arg(long)]
    spread: Option<f32>,
    /// Clump factor: 1 draws child tips onto the parent's tip, 0 none [scene, else 0].
    #[arg(long, allow_hyphen_values = true)]
    clump: Option<f32>,
    /// Curl radius, m (0 = no curl) [scene, else 0].
    #[arg(long)]
    curl_radius: Option<f32>,
    /// Curl frequency, turns per meter of hair [scene, else 0].
    #[arg(long)]
    curl_frequency: Option<f32>,
    /// Seed of the children's random values [scene, else 0].
    #[arg(long)]
    seed: Option<u64>,
}

impl ChildArgs {
    /// The overrides given.
    pub fn overrides(&self) -> ChildOverrides {
        let count = match (self.children_per_parent, self.count) {
            (_, Some(n)) => Some(ChildCount::Total(n)),
            (Some(n), None) => Some(ChildCount::PerParent(n)),
            (None, None) => None,
        };
        ChildOverrides {
            count,
            interpolated: self.mode.map(|m| matches!(m, ChildModeArg::Interpolated)),
            neighbours: self.neighbours,
            spread: self.spread,
            clump: self.clump,
            curl_radius: self.curl_radius,
            curl_frequency: self.curl_frequency,
            seed: self.seed,
        }
    }

    /// The first child option given, as its flag (to refuse it where no children are made).
    pub fn first_given(&self) -> Option<&'static str> {
        [
            (self.children_per_parent.is_some(), "--children-per-parent"),
            (self.count.is_some(), "--count"),
            (self.mode.is_some(), "--mode"),
            (self.neighbours.is_some(), "--neighbours"),
            (self.display, "--display"),
            (self.spread.is_some(), "--spread"),
            (self.clump.is_some(), "--clump"),
            (self.curl_radius.is_some(), "--curl-radius"),
            (self.curl_frequency.is_some(), "--curl-frequency"),
            (self.seed.is_some(), "--seed"),
        ]
        .into_iter()
        .find_map(|(given, flag)| given.then_some(flag))
    }
}

/// Child distribution.
#[derive(Clone, Copy, ValueEnum)]
pub enum ChildModeArg {
    /// Grouped around one parent.
    Simple,
    /// Between several parents.
    Interpolated,
}

/// Chunk compression of the cache.
#[derive(Clone, Copy, ValueEnum)]
pub enum CompressionArg {
    /// No compression: fastest to write and read; simulated hair barely compresses.
    None,
    /// LZ4: about 1 % smaller on moving hair, half the size for still hair; 2.7× slower writes.
    Lz4,
    /// Zstandard: about 9 % smaller on moving hair, slower to write.
    Zstd,
}

impl From<CompressionArg> for Compression {
    fn from(c: CompressionArg) -> Self {
        match c {
            CompressionArg::None => Compression::None,
            CompressionArg::Lz4 => Compression::Lz4,
            CompressionArg::Zstd => Compression::Zstd,
        }
    }
}

/// Environment variable choosing the compiled copy of the mass-spring kernel: `baseline` runs
/// the portable copy on any CPU (to compare speeds, or to check on one machine that both copies
/// give the same bits); unset or `auto`, the fastest copy the CPU has.
const KERNEL_ENV: &str = "HAIRSYS_KERNEL";

/// The kernel copy [`KERNEL_ENV`] asks for; an error names the variable, its value and the
/// accepted values.
pub fn kernel_from_env() -> Result<KernelChoice, CliError> {
    match std::env::var(KERNEL_ENV) {
        Err(std::env::VarError::NotPresent) => Ok(KernelChoice::Auto),
        Ok(v) if v == "auto" => Ok(KernelChoice::Auto),
        Ok(v) if v == "baseline" => Ok(KernelChoice::Baseline),
        other => Err(CliError::input(format!(
            "{KERNEL_ENV} = {:?}: set it to `baseline` (the portable kernel copy) or `auto` (the \
             fastest copy this CPU runs), or unset it",
            other.unwrap_or_else(|e| e.to_string())
        ))),
    }
}

/// A part of a `--frames` value that is not a frame number.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "`{given}` is not a frame number (whole number ≥ 0); write FIRST-LAST, e.g. 1-48, or one \
     frame N"
)]
pub struct NotAFrame {
    /// The part given.
    pub given: String,
    /// The parser's error.
    pub source: std::num::ParseIntError,
}

/// Parses `--frames FIRST-LAST`, or `N` as the range of one frame `N-N`.
pub fn parse_range(s: &str) -> Result<(u32, u32), NotAFrame> {
    let num = |t: &str| {
        t.trim().parse::<u32>().map_err(|source| NotAFrame {
            given: t.to_string(),
            source,
        })
    };
    match s.split_once('-') {
        Some((a, b)) => Ok((num(a)?, num(b)?)),
        None => num(s).map(|n| (n, n)),
    }
}
