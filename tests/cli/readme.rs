//! Every command block of the README runs as written.
//!
//! The `bearing-ident …` lines, and the `cargo run --release --features cli -- …` lines as the
//! tool they build, run one after another in a temporary directory holding a copy of
//! `examples/field/`, `examples/tdms/` and `tests/mat/fixtures/` (the paths the README names), as a
//! reader types them, with the
//! `bearing-ident` of this build first on `PATH`. Running cargo inside a test would build the
//! crate again, so the other cargo lines are checked against the manifests as written: the
//! package (`-p`), its features and the required features of the target run, the example, test
//! and fuzz targets named, and the lock kept by `cargo install` (`--locked`); the `--` options
//! of a tool line that is not run (a block of [`NOT_RUN`]) against the subcommand's `--help`.
//! `bash`, `pip` and `python` lines name files of the repository. A line of any other form
//! fails the test: a new kind of README command needs its check here. The Python blocks run in
//! the Python package's tests (`python/tests/test_readme.py`).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Blocks whose tool lines are checked against `--help` but not run, by their heading, and why.
const NOT_RUN: &[(&str, &str)] = &[
    (
        "## Nonlinear elements",
        "two 32 s random records with friction, simulated and identified by the reverse path, \
         take 19 s in the test build (tests/nonlinear/end_to_end.rs runs that identification)",
    ),
    (
        "## Test campaigns",
        "the plan reads the records the campaign example writes",
    ),
];

/// One command of a README `sh` block: the heading it is under and its text (continuation
/// lines joined, the comment after `#` removed).
#[derive(Debug, Clone, PartialEq)]
struct Line {
    heading: String,
    text: String,
}

/// The command lines of every ```` ```sh ```` block of `readme`, in order.
fn commands(readme: &str) -> Vec<Line> {
    let mut out = Vec::new();
    let mut heading = String::new();
    let mut in_block = false;
    let mut pending = String::new();
    for raw in readme.lines() {
        if !in_block {
            if raw.starts_with("## ") {
                heading = raw.trim().to_owned();
            }
            in_block = raw.trim() == "```sh";
            continue;
        }
        if raw.trim() == "```" {
            in_block = false;
            continue;
        }
        let line = raw.trim();
        if let Some(first) = line.strip_suffix('\\') {
            pending.push_str(first.trim());
            pending.push(' ');
            continue;
        }
        let whole = std::mem::take(&mut pending) + line;
        let text = whole.split(" #").next().unwrap_or("").trim().to_owned();
        if !text.is_empty() && !text.starts_with('#') {
            out.push(Line {
                heading: heading.clone(),
                text,
            });
        }
    }
    out
}

/// A cargo manifest (`Cargo.toml`) of the repository.
fn manifest(root: &Path, relative: &str) -> toml::Table {
    let text =
        std::fs::read_to_string(root.join(relative)).unwrap_or_else(|e| panic!("{relative}: {e}"));
    text.parse()
        .unwrap_or_else(|e| panic!("{relative} does not parse: {e}"))
}

/// The features `given` turn on in `manifest`, through the features they enable.
fn enabled(manifest: &toml::Table, given: &[String]) -> BTreeSet<String> {
    let table = manifest.get("features").and_then(|f| f.as_table());
    let mut on = BTreeSet::new();
    let mut todo: Vec<String> = given.to_vec();
    while let Some(f) = todo.pop() {
        let Some(implied) = table.and_then(|t| t.get(&f)).and_then(|v| v.as_array()) else {
            continue;
        };
        if on.insert(f) {
            todo.extend(
                implied
                    .iter()
                    .filter_map(|v| v.as_str())
                    .filter(|v| !v.contains(':') && !v.contains('/'))
                    .map(str::to_owned),
            );
        }
    }
    on
}

/// The target of kind `kind` (`bin`, `example`) named `name` in `manifest`, if declared.
fn target<'a>(manifest: &'a toml::Table, kind: &str, name: &str) -> Option<&'a toml::Table> {
    manifest
        .get(kind)?
        .as_array()?
        .iter()
        .filter_map(|t| t.as_table())
        .find(|t| t.get("name").and_then(|n| n.as_str()) == Some(name))
}

/// The required features of a target.
fn required(target: &toml::Table) -> Vec<String> {
    target
        .get("required-features")
        .and_then(|r| r.as_array())
        .map(|r| {
            r.iter()
                .filter_map(|v| v.as_str().map(str::to_owned))
                .collect()
        })
        .unwrap_or_default()
}

/// What a `cargo` line asks for, its options read as cargo reads them.
#[derive(Debug, Default)]
struct Cargo {
    subcommand: String,
    package: Option<String>,
    features: Vec<String>,
    all_features: bool,
    locked: bool,
    path: Option<String>,
    example: Option<String>,
    tests: Vec<String>,
    /// What follows `--`.
    rest: Vec<String>,
    /// Words that are not options (`fuzz run TARGET`).
    words: Vec<String>,
}

/// Parses the words after `cargo`; an option this test does not know is an error.
fn parse_cargo(words: &[&str]) -> Result<Cargo, String> {
    let mut c = Cargo::default();
    let mut it = words.iter().map(|w| w.to_string());
    while let Some(w) = it.next() {
        let mut value = |name: &str| it.next().ok_or(format!("{name} without its value"));
        match w.as_str() {
            "--" => {
                c.rest = it.by_ref().collect();
            }
            "--release" | "--open" | "--no-deps" | "--no-run" | "-v" => {}
            "--locked" => c.locked = true,
            "--all-features" => c.all_features = true,
            "--features" => c
                .features
                .extend(value("--features")?.split(',').map(str::to_owned)),
            "-p" | "--package" => c.package = Some(value("-p")?),
            "--path" => c.path = Some(value("--path")?),
            "--example" => c.example = Some(value("--example")?),
            "--test" => c.tests.push(value("--test")?),
            "-s" if c.subcommand == "fuzz" => {
                value("-s")?;
            }
            w if w.starts_with('+') => {}
            w if w.starts_with('-') => return Err(format!("cargo option `{w}` unknown here")),
            w if c.subcommand.is_empty() => c.subcommand = w.to_owned(),
            w => c.words.push(w.to_owned()),
        }
    }
    Ok(c)
}

/// Checks a `cargo` line against the manifests. Returns the tool's arguments when the line runs
/// the command-line tool (`cargo run --features cli -- ARGS`).
fn check_cargo(root: &Path, line: &str) -> Result<Option<Vec<String>>, String> {
    let words: Vec<&str> = line.split_whitespace().skip(1).collect();
    let c = parse_cargo(&words)?;
    let root_manifest = manifest(root, "Cargo.toml");
    let members: Vec<String> = root_manifest["workspace"]["members"]
        .as_array()
        .ok_or("no workspace members")?
        .iter()
        .filter_map(|m| m.as_str().map(str::to_owned))
        .collect();
    let package_manifest = match &c.package {
        None => root_manifest.clone(),
        Some(name) => members
            .iter()
            .map(|m| (m, manifest(root, &format!("{m}/Cargo.toml"))))
            .find(|(_, t)| t["package"]["name"].as_str() == Some(name))
            .map(|(_, t)| t)
            .ok_or(format!("no workspace package `{name}`"))?,
    };
    let all: Vec<String> = package_manifest
        .get("features")
        .and_then(|f| f.as_table())
        .map(|t| t.keys().cloned().collect())
        .unwrap_or_default();
    for f in &c.features {
        if !all.contains(f) {
            return Err(format!("feature `{f}` is not one of the package's {all:?}"));
        }
    }
    let on = if c.all_features {
        enabled(&package_manifest, &all)
    } else {
        enabled(&package_manifest, &c.features)
    };
    let needs = |t: &toml::Table, what: &str| -> Result<(), String> {
        let missing: Vec<String> = required(t)
            .into_iter()
            .filter(|f| !on.contains(f))
            .collect();
        if missing.is_empty() {
            Ok(())
        } else {
            Err(format!("{what} needs the features {missing:?}"))
        }
    };
    let tool = || -> Result<(), String> {
        let bin = target(&root_manifest, "bin", "bearing-ident").ok_or("no bin")?;
        needs(bin, "the tool")
    };
    match c.subcommand.as_str() {
        "install" => {
            if c.path.as_deref() != Some(".") {
                return Err("the crate is installed from the checkout: `--path .`".into());
            }
            if !c.locked {
                return Err(
                    "`cargo install` without `--locked` resolves newer versions than \
                            Cargo.lock, and `cargo run` then builds everything again"
                        .into(),
                );
            }
            tool()?;
            Ok(None)
        }
        "run" => match &c.example {
            Some(example) => {
                let t = target(&package_manifest, "example", example)
                    .ok_or(format!("no example `{example}` in that package"))?;
                needs(t, &format!("example `{example}`"))?;
                if c.package.is_none() {
                    return Err("the examples are the package `bearing-ident-examples`".into());
                }
                Ok(None)
            }
            None => {
                if c.package.is_some() {
                    return Err("`cargo run -p …` without `--example`".into());
                }
                tool()?;
                Ok(Some(c.rest))
            }
        },
        "test" => {
            for t in &c.tests {
                let dir = root.join("tests").join(t).join("main.rs");
                let file = root.join("tests").join(format!("{t}.rs"));
                if !dir.is_file() && !file.is_file() {
                    return Err(format!("no test target `{t}`"));
                }
            }
            Ok(None)
        }
        "bench" | "doc" => Ok(None),
        "fuzz" => {
            let fuzz = manifest(root, "fuzz/Cargo.toml");
            let name = c.words.get(1).ok_or("fuzz run without a target")?;
            target(&fuzz, "bin", name).ok_or(format!("no fuzz target `{name}`"))?;
            Ok(None)
        }
        other => Err(format!(
            "cargo {other}: a subcommand this test does not check"
        )),
    }
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        if path.is_file() {
            std::fs::copy(&path, to.join(path.file_name().unwrap())).unwrap();
        }
    }
}

/// The `--` options `bearing-ident SUBCOMMAND --help` names: its options, and the aliases its
/// text names (`` (`--excitation` is the same flag) ``).
fn help_options(exe: &Path, subcommand: &str) -> BTreeSet<String> {
    let out = Command::new(exe)
        .args([subcommand, "--help"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{subcommand} --help: {out:?}");
    String::from_utf8_lossy(&out.stdout)
        .split(|c: char| !(c.is_alphanumeric() || c == '-'))
        .filter(|w| w.starts_with("--") && w.len() > 2)
        .map(str::to_owned)
        .collect()
}

/// What a README line is, once checked.
enum Step {
    /// A tool line to run: its text as `sh -c` takes it.
    Run(String),
    /// Checked, nothing to run.
    Checked,
}

fn step(root: &Path, exe: &Path, line: &Line) -> Result<Step, String> {
    let text = &line.text;
    let first = text.split_whitespace().next().unwrap_or("");
    let tool_args = match first {
        "bearing-ident" => Some(
            text.split_whitespace()
                .skip(1)
                .map(str::to_owned)
                .collect::<Vec<_>>(),
        ),
        "cargo" => check_cargo(root, text)?,
        "bash" | "python" => {
            let file = text.split_whitespace().nth(1).unwrap_or("");
            return if root.join(file).is_file() {
                Ok(Step::Checked)
            } else {
                Err(format!("no file `{file}`"))
            };
        }
        "pip" => {
            let folder = text.split_whitespace().last().unwrap_or("");
            return if root.join(folder).join("pyproject.toml").is_file() {
                Ok(Step::Checked)
            } else {
                Err(format!("`{folder}` is no Python package"))
            };
        }
        _ => return Err("a command this test does not know".into()),
    };
    let Some(args) = tool_args else {
        return Ok(Step::Checked);
    };
    let why = NOT_RUN.iter().find(|(h, _)| *h == line.heading);
    if why.is_none() {
        return Ok(Step::Run(format!("bearing-ident {}", args.join(" "))));
    }
    let subcommand = args.first().ok_or("the tool without a subcommand")?;
    let known = help_options(exe, subcommand);
    for option in args.iter().filter(|a| a.starts_with("--")) {
        let option = option.split('=').next().unwrap_or(option);
        if !known.contains(option) {
            return Err(format!("`{subcommand}` has no option `{option}`"));
        }
    }
    Ok(Step::Checked)
}

#[test]
fn every_readme_command_runs_as_written() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let lines = commands(&readme);
    let exe = PathBuf::from(env!("CARGO_BIN_EXE_bearing-ident"));
    let five = |l: &&Line| l.heading == "## CLI in five minutes";
    let first = lines
        .iter()
        .find(five)
        .expect("a `CLI in five minutes` block");
    assert!(
        first.text.starts_with("cargo install"),
        "the five-minute block starts by building the tool: {first:?}"
    );
    for command in ["demo", "simulate", "identify", "inspect", "field"] {
        assert!(
            lines
                .iter()
                .filter(five)
                .any(|l| l.text.starts_with(&format!("bearing-ident {command}"))),
            "the five-minute block shows `{command}`"
        );
    }

    let dir = tempfile::tempdir().unwrap();
    copy_dir(
        &root.join("examples/field"),
        &dir.path().join("examples/field"),
    );
    copy_dir(
        &root.join("examples/tdms"),
        &dir.path().join("examples/tdms"),
    );
    copy_dir(
        &root.join("tests/mat/fixtures"),
        &dir.path().join("tests/mat/fixtures"),
    );
    let path = std::env::join_paths(std::iter::once(exe.parent().unwrap().to_path_buf()).chain(
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()),
    ))
    .unwrap();
    let (mut ran, mut checked) = (0, 0);
    for line in &lines {
        let step = step(root, &exe, line)
            .unwrap_or_else(|e| panic!("README, {}: `{}`: {e}", line.heading, line.text));
        let Step::Run(command) = step else {
            checked += 1;
            continue;
        };
        let out = Command::new("sh")
            .arg("-c")
            .arg(&command)
            .current_dir(dir.path())
            .env("PATH", &path)
            .output()
            .expect("sh runs");
        assert!(
            out.status.success(),
            "README, {}: `{}` failed ({:?}):\n{}",
            line.heading,
            line.text,
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
        ran += 1;
    }
    assert!(ran >= 14 && checked >= 15, "ran {ran}, checked {checked}");
    // What the blocks say they leave behind.
    let result: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("result.json")).unwrap()).unwrap();
    assert_eq!(result["n"], 2, "{result}");
    for file in ["report/index.html", "field-report/index.html", "brg.toml"] {
        assert!(dir.path().join(file).is_file(), "{file}");
    }
}

#[test]
fn blocks_are_read_line_by_line_with_their_headings() {
    let readme = "intro\n## A\n\ntext\n\n```sh\ncargo install --path . --features cli  # x\n\n\
         bearing-ident demo\n# a comment\nbearing-ident simulate \\\n    --out r/   # y\n```\n\n\
         ## B\n```python\nno\n```\n```sh\nbash .ci/test\n```\n";
    let lines = commands(readme);
    let texts: Vec<(&str, &str)> = lines
        .iter()
        .map(|l| (l.heading.as_str(), l.text.as_str()))
        .collect();
    assert_eq!(
        texts,
        [
            ("## A", "cargo install --path . --features cli"),
            ("## A", "bearing-ident demo"),
            ("## A", "bearing-ident simulate --out r/"),
            ("## B", "bash .ci/test"),
        ]
    );
}

/// The checks fail on the commands a reader could not run as written.
#[test]
fn commands_that_cannot_run_as_written_are_refused() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let exe = PathBuf::from(env!("CARGO_BIN_EXE_bearing-ident"));
    let refused = |heading: &str, text: &str| {
        let line = Line {
            heading: heading.into(),
            text: text.into(),
        };
        match step(root, &exe, &line) {
            Ok(_) => panic!("`{text}` passed"),
            Err(e) => e,
        }
    };
    // The example needs its package; the crate is not published; a lock not kept.
    assert!(refused("## Try it", "cargo run --release --example campaign").contains("package"));
    assert!(refused("## A", "cargo install bearing-ident --features cli").contains("--path ."));
    assert!(refused("## A", "cargo install --path . --features cli").contains("--locked"));
    // The tool without its feature; a feature the package does not have.
    assert!(refused("## A", "cargo run --release -- demo").contains("features"));
    assert!(refused("## A", "cargo run --release --features plots -- demo").contains("`plots`"));
    // No such example, test target or option.
    assert!(
        refused(
            "## A",
            "cargo run --release -p bearing-ident-examples --example quickstrat"
        )
        .contains("quickstrat")
    );
    assert!(refused("## A", "cargo test --all-features --test estimaton").contains("estimaton"));
    assert!(
        refused(
            "## Test campaigns",
            "cargo run --release --features cli -- campaign plan.toml --plots out"
        )
        .contains("--plots")
    );
    assert!(refused("## A", "make install").contains("does not know"));
}
