//! `hairsys farm job`: the OpenJD job bundle of a shot (see the [module](super) docs for the
//! steps).
//!
//! | file | what |
//! |---|---|
//! | `template.yaml` | the job template, `jobtemplate-2023-09` with the `TASK_CHUNKING` extension |
//! | `parameter_values.yaml` | the job parameters' values (Deadline Cloud's `parameterValues` list) |
//! | `job_parameters.yaml` | the same values as one mapping, for `openjd run -p file://…` |
//! | `asset_references.yaml` | the shot and scene files as inputs, the output folder as output (Deadline Cloud job attachments) |
//! | `commands.txt` | every task as one command line, step by step, for other farm managers |
//!
//! Job parameters: `ShotFile` (`PATH`, a file read), `OutputDir` (`PATH`, a folder written),
//! `ChunkSize` (`INT`, frames per Export task, 1–[`MAX_CHUNK_SIZE`]) and `Hairsys` (`STRING`,
//! the command that runs hairsys on a worker). `parameter_values.yaml` and
//! `job_parameters.yaml` give the values the bundle was written with (absolute paths). The
//! template gives defaults to `ChunkSize` and `Hairsys` only: OpenJD takes a `PATH` default
//! only relative to the template's folder and inside it.

use std::path::{Component, Path, PathBuf};

use super::yaml::Yaml;
use super::{chunks, write_atomic, FarmError, MAX_CHUNK_SIZE};
use crate::shot::ShotFile;

/// How the job is written.
#[derive(Debug, Clone)]
pub struct JobOptions {
    /// Frames per Export task (the `ChunkSize` parameter's default), 1–[`MAX_CHUNK_SIZE`].
    pub chunk_size: u32,
    /// Where the tasks write (the `OutputDir` parameter's default); made absolute.
    pub output_dir: PathBuf,
    /// The command that runs hairsys on a worker (the `Hairsys` parameter's default), e.g.
    /// `hairsys` on `PATH` or an absolute path.
    pub hairsys: String,
}

/// What [`write_job`] wrote.
#[derive(Debug, Clone, serde::Serialize)]
pub struct JobSummary {
    /// The bundle folder.
    pub bundle: PathBuf,
    /// The files written in it.
    pub files: Vec<PathBuf>,
    /// The job's name.
    pub name: String,
    /// The shot file, absolute (the `ShotFile` default).
    pub shot_file: PathBuf,
    /// The output folder, absolute (the `OutputDir` default).
    pub output_dir: PathBuf,
    /// Frames per Export task (the `ChunkSize` default).
    pub chunk_size: u32,
    /// The shot's digest the tasks check.
    pub digest: String,
    /// Tasks of each step, with the default chunk size: (step, tasks).
    pub tasks: Vec<(String, usize)>,
}

/// One task as a command line: its step and its arguments after the hairsys command.
#[derive(Debug, Clone, PartialEq)]
pub struct TaskCommand {
    /// `Simulate`, `Export` or `Assemble`.
    pub step: &'static str,
    /// The arguments.
    pub args: Vec<String>,
}

/// Writes the job bundle of `shot` into folder `bundle` (created if needed; its files replaced
/// atomically).
pub fn write_job(
    shot: &ShotFile,
    bundle: &Path,
    opts: &JobOptions,
) -> Result<JobSummary, FarmError> {
    if !(1..=MAX_CHUNK_SIZE).contains(&opts.chunk_size) {
        return Err(FarmError::ChunkSize(opts.chunk_size));
    }
    let shot_file = std::fs::canonicalize(&shot.path)
        .map_err(|e| FarmError::io(&shot.path, format!("cannot resolve the path ({e})")))?;
    let output_dir = absolute(&opts.output_dir)?;
    super::create_dir(bundle)?;
    let name = job_name(shot);
    let template = template(shot, &name, opts);
    let values = Yaml::map([(
        "parameterValues",
        Yaml::List(vec![
            param_value("ShotFile", Yaml::str(shot_file.display().to_string())),
            param_value("OutputDir", Yaml::str(output_dir.display().to_string())),
            param_value("ChunkSize", Yaml::Int(i64::from(opts.chunk_size))),
            param_value("Hairsys", Yaml::str(&opts.hairsys)),
        ]),
    )]);
    let mapping = Yaml::map([
        ("ShotFile", Yaml::str(shot_file.display().to_string())),
        ("OutputDir", Yaml::str(output_dir.display().to_string())),
        ("ChunkSize", Yaml::Int(i64::from(opts.chunk_size))),
        ("Hairsys", Yaml::str(&opts.hairsys)),
    ]);
    let base = shot_file.parent().unwrap_or(Path::new("/"));
    let mut inputs = vec![shot_file.display().to_string()];
    for c in &shot.shot.characters {
        let scene = base.join(&c.scene);
        let scene = std::fs::canonicalize(&scene).unwrap_or(scene);
        let scene = scene.display().to_string();
        if !inputs.contains(&scene) {
            inputs.push(scene);
        }
    }
    let assets = Yaml::map([(
        "assetReferences",
        Yaml::map([
            (
                "inputs",
                Yaml::map([
                    ("filenames", Yaml::strs(&inputs)),
                    ("directories", Yaml::List(vec![])),
                ]),
            ),
            (
                "outputs",
                Yaml::map([(
                    "directories",
                    Yaml::strs([output_dir.display().to_string()]),
                )]),
            ),
        ]),
    )]);
    let commands = commands_text(shot, &shot_file, &output_dir, opts);
    let files = [
        ("template.yaml", template.to_document()),
        ("parameter_values.yaml", values.to_document()),
        ("job_parameters.yaml", mapping.to_document()),
        ("asset_references.yaml", assets.to_document()),
        ("commands.txt", commands),
    ];
    let mut written = Vec::new();
    for (file, text) in files {
        let path = bundle.join(file);
        write_atomic(&path, text.as_bytes())?;
        written.push(path);
    }
    let tasks = task_commands(shot, &shot_file, &output_dir, opts);
    let count = |step| tasks.iter().filter(|t| t.step == step).count();
    Ok(JobSummary {
        bundle: bundle.to_path_buf(),
        files: written,
        name,
        shot_file,
        output_dir,
        chunk_size: opts.chunk_size,
        digest: shot.digest.clone(),
        tasks: ["Simulate", "Export", "Assemble"]
            .into_iter()
            .map(|s| (s.to_string(), count(s)))
            .filter(|(_, n)| *n > 0)
            .collect(),
    })
}

/// `hairsys shot NAME` (the shot's name, else the shot file's stem).
fn job_name(shot: &ShotFile) -> String {
    let name = if shot.shot.shot.name.is_empty() {
        shot.path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    } else {
        shot.shot.shot.name.clone()
    };
    format!("hairsys shot {name}")
}

/// `path` made absolute against the current folder, `.` and `..` resolved lexically.
fn absolute(path: &Path) -> Result<PathBuf, FarmError> {
    let full = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir()
            .map_err(|e| FarmError::io(path, format!("cannot resolve the path ({e})")))?
            .join(path)
    };
    let mut out = PathBuf::new();
    for c in full.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    Ok(out)
}

fn param_value(name: &str, value: Yaml) -> Yaml {
    Yaml::map([("name", Yaml::str(name)), ("value", value)])
}

/// The arguments of every task with the job's defaults, step by step.
pub fn task_commands(
    shot: &ShotFile,
    shot_file: &Path,
    output_dir: &Path,
    opts: &JobOptions,
) -> Vec<TaskCommand> {
    let shot_arg = shot_file.display().to_string();
    let out_arg = output_dir.display().to_string();
    let common = |verb: &str| {
        vec![
            "farm".to_string(),
            verb.to_string(),
            shot_arg.clone(),
            "--out-dir".to_string(),
            out_arg.clone(),
            "--shot-digest".to_string(),
            shot.digest.clone(),
        ]
    };
    let mut tasks = Vec::new();
    for c in &shot.shot.characters {
        let mut args = common("simulate");
        args.extend(["--character".to_string(), c.name.clone(), "--quiet".into()]);
        tasks.push(TaskCommand {
            step: "Simulate",
            args,
        });
    }
    for c in shot.usd_characters() {
        for (a, b) in chunks(shot.frames(), opts.chunk_size) {
            let mut args = common("export");
            args.extend([
                "--character".to_string(),
                c.name.clone(),
                "--frames".into(),
                format!("{a}-{b}"),
                "--quiet".into(),
            ]);
            tasks.push(TaskCommand {
                step: "Export",
                args,
            });
        }
    }
    if shot.usd_characters().next().is_some() {
        let mut args = common("assemble");
        args.push("--quiet".into());
        tasks.push(TaskCommand {
            step: "Assemble",
            args,
        });
    }
    tasks
}

/// `commands.txt`: every task as one shell command line, step by step.
fn commands_text(
    shot: &ShotFile,
    shot_file: &Path,
    output_dir: &Path,
    opts: &JobOptions,
) -> String {
    let mut text = format!(
        "# {} — every task of the job as one command line, for farm managers that run command\n\
         # lines (OpenCue, Tractor, Deadline 10, a shell). Every task of a step may run at once;\n\
         # a step starts when every task of the step before it has finished. A failed task is\n\
         # retried by running its line again.\n",
        job_name(shot)
    );
    let mut step = "";
    for t in task_commands(shot, shot_file, output_dir, opts) {
        if t.step != step {
            step = t.step;
            text.push_str(&format!("\n# {step}\n"));
        }
        let line: Vec<String> = std::iter::once(opts.hairsys.as_str())
            .chain(t.args.iter().map(String::as_str))
            .map(shell_quote)
            .collect();
        text.push_str(&line.join(" "));
        text.push('\n');
    }
    text
}

/// `s` quoted for a POSIX shell where it needs it.
fn shell_quote(s: &str) -> String {
    let plain = !s.is_empty()
        && s.bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"-_./=:,+@%".contains(&b));
    if plain {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}

/// The job template (see the module docs).
fn template(shot: &ShotFile, name: &str, opts: &JobOptions) -> Yaml {
    // The task folders under `output_dir` are `super::layout`'s.
    let (first, last) = shot.frames();
    let digest = &shot.digest;
    let all: Vec<&str> = shot
        .shot
        .characters
        .iter()
        .map(|c| c.name.as_str())
        .collect();
    let usd: Vec<&str> = shot.usd_characters().map(|c| c.name.as_str()).collect();
    let task_args = |verb: &str, extra: &[&str]| {
        let mut args = vec![
            "farm",
            verb,
            "{{Param.ShotFile}}",
            "--out-dir",
            "{{Param.OutputDir}}",
            "--shot-digest",
            digest,
        ];
        args.extend_from_slice(extra);
        args.push("--quiet");
        Yaml::strs(args)
    };
    let script = |args: Yaml| {
        Yaml::map([(
            "actions",
            Yaml::map([(
                "onRun",
                Yaml::map([("command", Yaml::str("{{Param.Hairsys}}")), ("args", args)]),
            )]),
        )])
    };
    let mut steps = vec![Yaml::map([
        ("name", Yaml::str("Simulate")),
        (
            "description",
            Yaml::str(
                "One task per character: its simulation into NAME/NAME.mcap. A retried task \
                 continues the run its killed attempt left in NAME.mcap.partial.",
            ),
        ),
        (
            "parameterSpace",
            Yaml::map([(
                "taskParameterDefinitions",
                Yaml::List(vec![Yaml::map([
                    ("name", Yaml::str("Character")),
                    ("type", Yaml::str("STRING")),
                    ("range", Yaml::strs(&all)),
                ])]),
            )]),
        ),
        (
            "script",
            script(task_args(
                "simulate",
                &["--character", "{{Task.Param.Character}}"],
            )),
        ),
    ])];
    if !usd.is_empty() {
        steps.push(Yaml::map([
            ("name", Yaml::str("Export")),
            (
                "description",
                Yaml::str(
                    "Per character with USD output and per chunk of contiguous frames: \
                     NAME/chunks/NAME.FIRST-LAST.usdc, written atomically.",
                ),
            ),
            (
                "dependencies",
                Yaml::List(vec![Yaml::map([("dependsOn", Yaml::str("Simulate"))])]),
            ),
            (
                "parameterSpace",
                Yaml::map([(
                    "taskParameterDefinitions",
                    Yaml::List(vec![
                        Yaml::map([
                            ("name", Yaml::str("Character")),
                            ("type", Yaml::str("STRING")),
                            ("range", Yaml::strs(&usd)),
                        ]),
                        Yaml::map([
                            ("name", Yaml::str("Frames")),
                            ("type", Yaml::str("CHUNK[INT]")),
                            ("range", Yaml::str(format!("{first}-{last}"))),
                            (
                                "chunks",
                                Yaml::map([
                                    ("defaultTaskCount", Yaml::str("{{Param.ChunkSize}}")),
                                    ("rangeConstraint", Yaml::str("CONTIGUOUS")),
                                ]),
                            ),
                        ]),
                    ]),
                )]),
            ),
            (
                "script",
                script(task_args(
                    "export",
                    &[
                        "--character",
                        "{{Task.Param.Character}}",
                        "--frames",
                        "{{Task.Param.Frames}}",
                    ],
                )),
            ),
        ]));
        steps.push(Yaml::map([
            ("name", Yaml::str("Assemble")),
            (
                "description",
                Yaml::str(
                    "Per character a layer stitching its chunks with USD value clips \
                     (NAME/NAME.usda), and shot.usda referencing every character.",
                ),
            ),
            (
                "dependencies",
                Yaml::List(vec![Yaml::map([("dependsOn", Yaml::str("Export"))])]),
            ),
            ("script", script(task_args("assemble", &[]))),
        ]));
    }
    Yaml::map([
        ("specificationVersion", Yaml::str("jobtemplate-2023-09")),
        ("extensions", Yaml::strs(["TASK_CHUNKING"])),
        ("name", Yaml::str(name)),
        (
            "description",
            Yaml::str(format!(
                "Hair of {} character(s), frames {first}-{last}: simulate, export chunks, \
                 assemble shot.usda. Written by `hairsys farm job`.",
                all.len()
            )),
        ),
        (
            "parameterDefinitions",
            Yaml::List(vec![
                Yaml::map([
                    ("name", Yaml::str("ShotFile")),
                    ("type", Yaml::str("PATH")),
                    ("objectType", Yaml::str("FILE")),
                    ("dataFlow", Yaml::str("IN")),
                    (
                        "description",
                        Yaml::str("The shot file; its scenes are found relative to it."),
                    ),
                ]),
                Yaml::map([
                    ("name", Yaml::str("OutputDir")),
                    ("type", Yaml::str("PATH")),
                    ("objectType", Yaml::str("DIRECTORY")),
                    ("dataFlow", Yaml::str("OUT")),
                    (
                        "description",
                        Yaml::str("Where the caches, chunks and shot.usda are written."),
                    ),
                ]),
                Yaml::map([
                    ("name", Yaml::str("ChunkSize")),
                    ("type", Yaml::str("INT")),
                    ("description", Yaml::str("Frames per Export task.")),
                    ("default", Yaml::Int(i64::from(opts.chunk_size))),
                    ("minValue", Yaml::Int(1)),
                    ("maxValue", Yaml::Int(i64::from(MAX_CHUNK_SIZE))),
                ]),
                Yaml::map([
                    ("name", Yaml::str("Hairsys")),
                    ("type", Yaml::str("STRING")),
                    (
                        "description",
                        Yaml::str("The command that runs hairsys on a worker."),
                    ),
                    ("default", Yaml::str(&opts.hairsys)),
                ]),
            ]),
        ),
        ("steps", Yaml::List(steps)),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shell_quoting_leaves_plain_words_and_quotes_the_rest() {
        assert_eq!(shell_quote("/a/b-c_d.toml"), "/a/b-c_d.toml");
        assert_eq!(shell_quote("a b"), "'a b'");
        assert_eq!(shell_quote("it's"), "'it'\\''s'");
        assert_eq!(shell_quote(""), "''");
    }

    #[test]
    fn absolute_paths_resolve_dots_lexically() {
        assert_eq!(
            absolute(Path::new("/a/./b/../c")).unwrap(),
            PathBuf::from("/a/c")
        );
    }
}
