//! The README's "CLI in five minutes" block runs as written: every command line of its first
//! `sh` block, with the `bearing-ident` of this build first on `PATH`, in a temporary directory
//! holding a copy of `examples/field/` (the paths the block names), one after another as a
//! reader types them. The `cargo install` line is what puts the tool on `PATH`, so it is the
//! one line not run.

use std::path::Path;
use std::process::Command;

/// The heading of the block in README.md.
const HEADING: &str = "## CLI in five minutes";

/// The command lines of the first ```` ```sh ```` block after [`HEADING`].
fn block(readme: &str) -> Vec<&str> {
    let after = readme
        .split_once(HEADING)
        .unwrap_or_else(|| panic!("README.md has no `{HEADING}`"))
        .1;
    let body = after
        .split_once("```sh\n")
        .expect("an sh block after the heading")
        .1;
    let body = body.split_once("```").expect("the block closes").0;
    body.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .collect()
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

#[test]
fn cli_in_five_minutes_runs_as_written() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let lines = block(&readme);
    let (install, commands): (Vec<&str>, Vec<&str>) =
        lines.into_iter().partition(|l| l.starts_with("cargo "));
    assert_eq!(install.len(), 1, "one `cargo install` line: {install:?}");
    assert!(install[0].starts_with("cargo install --path . --features cli"));
    assert!(commands.len() >= 6, "{commands:?}");
    assert!(
        commands.iter().all(|c| c.starts_with("bearing-ident ")),
        "every other line runs the tool: {commands:?}"
    );
    for command in ["demo", "simulate", "identify", "inspect", "field"] {
        assert!(
            commands
                .iter()
                .any(|c| c.starts_with(&format!("bearing-ident {command} "))
                    || *c == format!("bearing-ident {command}")),
            "the block shows `{command}`"
        );
    }

    let dir = tempfile::tempdir().unwrap();
    copy_dir(
        &root.join("examples/field"),
        &dir.path().join("examples/field"),
    );
    let exe = Path::new(env!("CARGO_BIN_EXE_bearing-ident"));
    let path = std::env::join_paths(std::iter::once(exe.parent().unwrap().to_path_buf()).chain(
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()),
    ))
    .unwrap();
    for command in &commands {
        let out = Command::new("sh")
            .arg("-c")
            .arg(command)
            .current_dir(dir.path())
            .env("PATH", &path)
            .output()
            .expect("sh runs");
        assert!(
            out.status.success(),
            "`{command}` failed ({:?}):\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
    }
    // What the block says it leaves behind.
    let result: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("result.json")).unwrap()).unwrap();
    assert_eq!(result["n"], 2, "{result}");
    assert!(dir.path().join("report/index.html").is_file());
}

#[test]
fn the_block_is_parsed_line_by_line() {
    let readme = format!(
        "intro\n{HEADING}\n\ntext\n\n```sh\ncargo install --path . --features cli  # x\n\n\
         bearing-ident demo\n# a comment\nbearing-ident simulate --out r/   # y\n```\n\n```sh\nno\n```\n"
    );
    assert_eq!(
        block(&readme),
        [
            "cargo install --path . --features cli  # x",
            "bearing-ident demo",
            "bearing-ident simulate --out r/   # y"
        ]
    );
}
