//! Every command block of the README and of the guide (`docs/guide/*.md`) runs as written, and
//! prints what the document quotes.
//!
//! Each document runs in a temporary directory of its own holding a copy of `examples/field/`,
//! `examples/tdms/` and `tests/mat/fixtures/` (the paths the documents name), with the
//! `bearing-ident` of this build first on `PATH`. Its `bearing-ident …` lines, and the
//! `cargo run --release --features cli -- …` lines as the tool they build, run one after another
//! as a reader types them. Running cargo inside a test would build the crate again, so the other
//! cargo lines are checked against the manifests as written: the package (`-p`), its features
//! and the required features of the target run, the example, test and fuzz targets named, and
//! the lock kept by `cargo install` (`--locked`); the `--` options of a tool line that is not
//! run (a block of [`NOT_RUN`]) against the subcommand's `--help`. `bash`, `pip` and `python`
//! lines name files of the repository. A line of any other form fails the test: a new kind of
//! command needs its check here.
//!
//! A ```` ```sh ```` block followed (after blank lines only) by a ```` ```text ```` block quotes
//! its output: the standard output of the block's commands, one after another, is compared with
//! the quoted text line by line, trailing blanks and blank lines at the end aside. Two marks
//! stand for what varies from run to run (a time in milliseconds): `[..]` within a line matches
//! any text, a line `...` any number of lines. Nothing else is loosened: numbers are compared as
//! printed (the simulations are seeded). The Python blocks run in the Python package's tests
//! (`python/tests/test_readme.py`), by the same rules.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Blocks whose tool lines are checked against `--help` but not run, by their document and
/// heading, and why.
const NOT_RUN: &[(&str, &str, &str)] = &[
    (
        "docs/guide/07-nonlinear.md",
        "## Identifying friction",
        "two 32 s random records with friction, simulated and identified by the reverse path, \
         take 19 s in the test build (tests/nonlinear/end_to_end.rs runs that identification)",
    ),
    (
        "docs/guide/05-campaigns.md",
        "## The example campaign",
        "the plan reads the records the campaign example writes",
    ),
    (
        "docs/guide/10-rotor.md",
        "## A campaign over speed, to ROSS stochastic bearings",
        "the plan is the reader's own file (shown, not shipped)",
    ),
];

/// The guide's chapters, in reading order; each has its test below, so that they run side by
/// side (`every_chapter_has_its_test` keeps the list whole).
const CHAPTERS: &[&str] = &[
    "01-one-test-point.md",
    "02-excitation.md",
    "03-estimators.md",
    "04-error-bars.md",
    "05-campaigns.md",
    "06-field.md",
    "07-nonlinear.md",
    "08-element-models.md",
    "09-lab-files.md",
    "10-rotor.md",
    "reference-cli.md",
    "reference-output.md",
    "reference-performance.md",
];

/// One command of a `sh` block: the heading it is under and its text (continuation lines
/// joined, the comment after `#` removed).
#[derive(Debug, Clone, PartialEq)]
struct Line {
    heading: String,
    text: String,
}

/// A ```` ```sh ```` block: its commands, and the output it quotes, if it does.
#[derive(Debug, Clone, PartialEq)]
struct Block {
    heading: String,
    commands: Vec<Line>,
    quoted: Option<String>,
}

/// The ```` ```sh ```` blocks of `document`, in order, each with the ```` ```text ```` block
/// that follows it, if one does.
fn blocks(document: &str) -> Vec<Block> {
    let mut out: Vec<Block> = Vec::new();
    let mut heading = String::new();
    // What the reader is in: prose, a sh block, a text block, or another block.
    #[derive(PartialEq)]
    enum In {
        Prose,
        Sh,
        Text,
        Other,
    }
    let mut state = In::Prose;
    // The last sh block closed, with only blank lines since.
    let mut open_for_output = false;
    let mut pending = String::new();
    let mut text = String::new();
    for raw in document.lines() {
        match state {
            In::Prose => {
                let fence = raw.trim();
                if raw.starts_with("## ") {
                    heading = raw.trim().to_owned();
                }
                if fence == "```sh" {
                    out.push(Block {
                        heading: heading.clone(),
                        commands: Vec::new(),
                        quoted: None,
                    });
                    state = In::Sh;
                } else if fence == "```text" && open_for_output {
                    text.clear();
                    state = In::Text;
                } else if fence.starts_with("```") {
                    state = In::Other;
                }
                open_for_output = open_for_output && fence.is_empty();
            }
            In::Sh => {
                let line = raw.trim();
                if line == "```" {
                    state = In::Prose;
                    open_for_output = true;
                    continue;
                }
                if let Some(first) = line.strip_suffix('\\') {
                    pending.push_str(first.trim());
                    pending.push(' ');
                    continue;
                }
                let whole = std::mem::take(&mut pending) + line;
                let command = whole.split(" #").next().unwrap_or("").trim().to_owned();
                if !command.is_empty() && !command.starts_with('#') {
                    let block = out.last_mut().expect("an open block");
                    block.commands.push(Line {
                        heading: block.heading.clone(),
                        text: command,
                    });
                }
            }
            In::Text => {
                if raw.trim() == "```" {
                    out.last_mut().expect("a block before").quoted = Some(text.clone());
                    state = In::Prose;
                } else {
                    text.push_str(raw);
                    text.push('\n');
                }
            }
            In::Other => {
                if raw.trim() == "```" {
                    state = In::Prose;
                }
            }
        }
    }
    out
}

/// The command lines of every ```` ```sh ```` block of `document`, in order.
fn commands(document: &str) -> Vec<Line> {
    blocks(document)
        .into_iter()
        .flat_map(|b| b.commands)
        .collect()
}

/// Whether `actual` is what `quoted` says: line by line, trailing blanks and blank lines at the
/// end aside; `[..]` within a
/// quoted line matches any text, a quoted line `...` any number of lines. On a difference, the
/// first quoted line that does not match and what stood there.
fn matches(quoted: &str, actual: &str) -> Result<(), String> {
    fn line_matches(pattern: &str, line: &str) -> bool {
        let mut parts = pattern.split("[..]");
        let first = parts.next().unwrap_or("");
        let Some(mut rest) = line.strip_prefix(first) else {
            return false;
        };
        let parts: Vec<&str> = parts.collect();
        for (i, part) in parts.iter().enumerate() {
            if i + 1 == parts.len() {
                return rest.ends_with(part);
            }
            match rest.find(part) {
                Some(at) => rest = &rest[at + part.len()..],
                None => return false,
            }
        }
        rest.is_empty()
    }
    fn walk(q: &[&str], a: &[&str]) -> bool {
        match q.split_first() {
            None => a.is_empty(),
            Some((&"...", more)) => (0..=a.len()).any(|skip| walk(more, &a[skip..])),
            Some((p, more)) => a.first().is_some_and(|l| line_matches(p, l)) && walk(more, &a[1..]),
        }
    }
    let q: Vec<&str> = quoted.trim_end().lines().map(str::trim_end).collect();
    let a: Vec<&str> = actual.trim_end().lines().map(str::trim_end).collect();
    if walk(&q, &a) {
        return Ok(());
    }
    // The first line that differs, for the message (before any `...`).
    let at = q
        .iter()
        .zip(&a)
        .take_while(|(p, l)| **p != "..." && line_matches(p, l))
        .count();
    Err(format!(
        "quoted line {} `{}`, printed `{}`",
        at + 1,
        q.get(at).unwrap_or(&"(end)"),
        a.get(at).unwrap_or(&"(end)")
    ))
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

/// What a document's line is, once checked.
enum Step {
    /// A tool line to run: its text as `sh -c` takes it.
    Run(String),
    /// Checked, nothing to run.
    Checked,
}

fn step(root: &Path, exe: &Path, document: &str, line: &Line) -> Result<Step, String> {
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
    let why = NOT_RUN
        .iter()
        .find(|(d, h, _)| *d == document && *h == line.heading);
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

/// What running a document did: its lines run and checked, and the folder it ran in.
struct Ran {
    ran: usize,
    checked: usize,
    quoted: usize,
    dir: tempfile::TempDir,
}

/// Runs every command block of `document` (a path relative to the repository) in a fresh
/// folder, as a reader types them, and compares what each block quotes with what it printed.
fn run_document(document: &str) -> Ran {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text =
        std::fs::read_to_string(root.join(document)).unwrap_or_else(|e| panic!("{document}: {e}"));
    let exe = PathBuf::from(env!("CARGO_BIN_EXE_bearing-ident"));
    let dir = tempfile::tempdir().unwrap();
    for fixtures in ["examples/field", "examples/tdms", "tests/mat/fixtures"] {
        copy_dir(&root.join(fixtures), &dir.path().join(fixtures));
    }
    let path = std::env::join_paths(std::iter::once(exe.parent().unwrap().to_path_buf()).chain(
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()),
    ))
    .unwrap();
    let (mut ran, mut checked, mut quoted) = (0, 0, 0);
    for block in blocks(&text) {
        let mut printed = String::new();
        for line in &block.commands {
            let step = step(root, &exe, document, line)
                .unwrap_or_else(|e| panic!("{document}, {}: `{}`: {e}", line.heading, line.text));
            let Step::Run(command) = step else {
                assert!(
                    block.quoted.is_none(),
                    "{document}, {}: `{}` quotes an output but is not run",
                    line.heading,
                    line.text
                );
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
                "{document}, {}: `{}` failed ({:?}):\n{}",
                line.heading,
                line.text,
                out.status,
                String::from_utf8_lossy(&out.stderr)
            );
            printed.push_str(&String::from_utf8_lossy(&out.stdout));
            ran += 1;
        }
        if let Some(q) = &block.quoted {
            matches(q, &printed).unwrap_or_else(|e| {
                panic!(
                    "{document}, {}: the quoted output differs: {e}\nprinted:\n{printed}",
                    block.heading
                )
            });
            quoted += 1;
        }
    }
    Ran {
        ran,
        checked,
        quoted,
        dir,
    }
}

#[test]
fn every_readme_command_runs_as_written() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let lines = commands(&readme);
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
    let run = run_document("README.md");
    assert!(
        run.ran >= 9 && run.checked >= 5 && run.quoted >= 1,
        "ran {}, checked {}, quoted {}",
        run.ran,
        run.checked,
        run.quoted
    );
    // What the blocks say they leave behind.
    let result: serde_json::Value =
        serde_json::from_slice(&std::fs::read(run.dir.path().join("result.json")).unwrap())
            .unwrap();
    assert_eq!(result["n"], 2, "{result}");
    for file in ["report/index.html", "frf.uff"] {
        assert!(run.dir.path().join(file).is_file(), "{file}");
    }
}

/// Runs a chapter of the guide; a chapter that runs nothing, or quotes nothing it runs, has no
/// place among the tested ones.
fn chapter(name: &str) -> Ran {
    assert!(CHAPTERS.contains(&name), "{name} is not in CHAPTERS");
    run_document(&format!("docs/guide/{name}"))
}

#[test]
fn guide_01_one_test_point() {
    let run = chapter("01-one-test-point.md");
    assert!(
        run.ran >= 3 && run.quoted >= 2,
        "ran {}, quoted {}",
        run.ran,
        run.quoted
    );
}

#[test]
fn guide_02_excitation() {
    let run = chapter("02-excitation.md");
    assert!(
        run.ran >= 2 && run.quoted >= 1,
        "ran {}, quoted {}",
        run.ran,
        run.quoted
    );
}

#[test]
fn guide_03_estimators() {
    let run = chapter("03-estimators.md");
    assert!(
        run.ran >= 2 && run.quoted >= 1,
        "ran {}, quoted {}",
        run.ran,
        run.quoted
    );
}

#[test]
fn guide_04_error_bars() {
    let run = chapter("04-error-bars.md");
    assert!(
        run.ran >= 2 && run.quoted >= 1,
        "ran {}, quoted {}",
        run.ran,
        run.quoted
    );
}

#[test]
fn guide_05_to_10_and_the_reference() {
    for name in &CHAPTERS[4..] {
        chapter(name);
    }
}

/// Every Markdown file of `docs/guide/` but its index (`README.md`, no commands) is a chapter
/// with its test, and every chapter listed exists.
#[test]
fn every_chapter_has_its_test() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut found: Vec<String> = std::fs::read_dir(root.join("docs/guide"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md") && n != "README.md")
        .collect();
    found.sort();
    let mut listed: Vec<String> = CHAPTERS.iter().map(|c| c.to_string()).collect();
    listed.sort();
    assert_eq!(found, listed, "docs/guide/ and CHAPTERS differ");
}

/// The anchor GitHub gives a heading: lower case, punctuation but `-` and `_` dropped, spaces
/// turned into `-`.
fn anchor(heading: &str) -> String {
    heading
        .trim_start_matches('#')
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == '-' || *c == '_' || *c == ' ')
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// Every relative link of the README and the guide names a file of the repository, and an
/// anchor after `#` a heading of that file.
#[test]
fn every_relative_link_resolves() {
    assert_eq!(
        anchor("## JSON of `identify --json`"),
        "json-of-identify---json"
    );
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut documents = vec![root.join("README.md"), root.join("docs/guide/README.md")];
    documents.extend(CHAPTERS.iter().map(|c| root.join("docs/guide").join(c)));
    let mut checked = 0;
    for document in &documents {
        let text = std::fs::read_to_string(document).unwrap();
        for link in text.split("](").skip(1) {
            let target = &link[..link.find(')').unwrap_or(link.len())];
            if target.starts_with("http") || target.contains(' ') {
                continue;
            }
            let (file, fragment) = target.split_once('#').unwrap_or((target, ""));
            let path = if file.is_empty() {
                document.clone()
            } else {
                document.parent().unwrap().join(file)
            };
            assert!(
                path.exists(),
                "{}: the link `{target}` names no file",
                document.display()
            );
            if !fragment.is_empty() {
                let headings = std::fs::read_to_string(&path).unwrap();
                assert!(
                    headings
                        .lines()
                        .filter(|l| l.starts_with('#'))
                        .any(|l| anchor(l) == fragment),
                    "{}: the link `{target}` names no heading",
                    document.display()
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 40, "only {checked} links");
}

/// The output reference names every field of `identify --json` (with the options that add
/// fields) and of `field --json`.
#[test]
fn the_output_reference_names_every_json_field() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("docs/guide/reference-output.md")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let exe = PathBuf::from(env!("CARGO_BIN_EXE_bearing-ident"));
    let run = |args: &[&str]| -> serde_json::Value {
        let out = Command::new(&exe)
            .args(args)
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(out.status.success(), "{args:?}: {out:?}");
        serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{args:?}: {e}"))
    };
    run(&[
        "simulate",
        "--impacts",
        "2",
        "--noise",
        "0.05",
        "--json",
        "--out",
        "r",
    ]);
    let identify = run(&[
        "identify",
        "--band",
        "8,49",
        "--json",
        "--per-frequency",
        "--units",
        "us",
        "--clearance",
        "100um",
        "--load",
        "500N",
        "--speed",
        "1800rpm",
        "r/impact-dof0-0.csv",
        "r/impact-dof0-1.csv",
        "r/impact-dof1-0.csv",
        "r/impact-dof1-1.csv",
    ]);
    let field = run(&[
        "field",
        "--json",
        "--rotor",
        root.join("examples/field/ROTOR.json").to_str().unwrap(),
        "--tests",
        root.join("examples/field/TESTS_bearings.json")
            .to_str()
            .unwrap(),
    ]);
    let mut fields: Vec<String> = Vec::new();
    for value in [&identify, &field] {
        fields.extend(value.as_object().unwrap().keys().cloned());
    }
    fields.extend(field["bearings"][0].as_object().unwrap().keys().cloned());
    assert!(fields.len() > 60, "{fields:?}");
    for name in fields {
        assert!(
            text.contains(&format!("`{name}`")),
            "reference-output.md does not name the JSON field `{name}`"
        );
    }
}

/// The reference chapter names every option of every subcommand, under the subcommand's
/// heading (`## bearing-ident identify`), as `--help` lists them.
#[test]
fn the_cli_reference_lists_every_option() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let exe = PathBuf::from(env!("CARGO_BIN_EXE_bearing-ident"));
    let text = std::fs::read_to_string(root.join("docs/guide/reference-cli.md")).unwrap();
    for subcommand in [
        "identify", "simulate", "demo", "inspect", "field", "campaign",
    ] {
        let heading = format!("## `bearing-ident {subcommand}`");
        let start = text
            .find(&heading)
            .unwrap_or_else(|| panic!("reference-cli.md has no `{heading}`"));
        let section = &text[start + heading.len()..];
        let section = &section[..section.find("\n## ").unwrap_or(section.len())];
        let named: BTreeSet<&str> = section
            .split(|c: char| !(c.is_alphanumeric() || c == '-'))
            .filter(|w| w.starts_with("--"))
            .collect();
        for option in help_options(&exe, subcommand) {
            assert!(
                named.contains(option.as_str()),
                "reference-cli.md, {heading}: no `{option}`"
            );
        }
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

/// A text block right after a sh block is its output; one after prose is not; a sh block in a
/// text block's place is not read as output.
#[test]
fn a_text_block_after_a_command_block_is_its_output() {
    let doc = "## A\n```sh\nbearing-ident demo\n```\n\n```text\nDemo\n  x\n```\n\
         ## B\n```sh\nbearing-ident demo\n```\nprose\n```text\nnot output\n```\n\
         ```python\n```\n```text\nnot output either\n```\n";
    let b = blocks(doc);
    assert_eq!(b.len(), 2);
    assert_eq!(b[0].quoted.as_deref(), Some("Demo\n  x\n"));
    assert_eq!(b[1].quoted, None);
}

/// Quoted output is compared exactly, but for `[..]` in a line and `...` lines.
#[test]
fn quoted_output_is_compared_line_by_line_with_its_marks() {
    let printed = "a 1.5 ms\nb\nc\nd  \n";
    assert!(matches("a 1.5 ms\nb\nc\nd\n", printed).is_ok());
    assert!(matches("a [..] ms\n...\nd\n", printed).is_ok());
    assert!(matches("a [..]\nb\n...\n", printed).is_ok());
    assert!(matches("...\n", printed).is_ok());
    assert!(
        matches("a 1.6 ms\nb\nc\nd\n", printed)
            .unwrap_err()
            .contains("line 1")
    );
    assert!(
        matches("a [..] ms\nb\nc\n", printed).is_err(),
        "a line left over"
    );
    assert!(
        matches("a [..] ms\nb\nx\nd\n", printed)
            .unwrap_err()
            .contains("`x`")
    );
    assert!(matches("[..]1.5[..]\n...\n", printed).is_ok());
    assert!(matches("[..]2.5[..]\n...\n", printed).is_err());
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
        match step(root, &exe, "docs/guide/05-campaigns.md", &line) {
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
            "## The example campaign",
            "cargo run --release --features cli -- campaign plan.toml --plots out"
        )
        .contains("--plots")
    );
    assert!(refused("## A", "make install").contains("does not know"));
}
