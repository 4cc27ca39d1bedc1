//! The `msd` binary as a user installs it: copied out of the build into a folder of its
//! own and run from a folder outside the workspace, with the paper's config beside it.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

/// `msd` copied once into a `bin/` folder of its own, as `cargo install` would put it on
/// the PATH. Once: copying while another test thread forks would leave the copy's write
/// handle in that child, and running the copy would then fail with "text file busy".
fn installed() -> PathBuf {
    static INSTALLED: OnceLock<PathBuf> = OnceLock::new();
    INSTALLED
        .get_or_init(|| {
            let bin = Path::new(env!("CARGO_TARGET_TMPDIR"))
                .join("installed")
                .join("bin");
            std::fs::create_dir_all(&bin).unwrap();
            let exe = bin.join(Path::new(env!("CARGO_BIN_EXE_msd")).file_name().unwrap());
            std::fs::copy(env!("CARGO_BIN_EXE_msd"), &exe).unwrap();
            exe
        })
        .clone()
}

fn msd(exe: &Path, args: &[&str], cwd: &Path) -> Output {
    Command::new(exe)
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("msd runs")
}

fn workspace_config(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../configs")
        .join(name)
}

/// results.json without the wall times (they differ between runs) and the command line.
fn stable(mut v: serde_json::Value) -> serde_json::Value {
    if let Some(map) = v.as_object_mut() {
        map.remove("timings_ms");
    }
    v
}

#[test]
fn installed_msd_runs_the_paper_outside_the_workspace_as_the_library_does() {
    let dir = tempfile::tempdir().unwrap();
    let exe = installed();
    let lab = dir.path().join("lab");
    std::fs::create_dir_all(&lab).unwrap();
    std::fs::copy(workspace_config("paper.toml"), lab.join("paper.toml")).unwrap();

    let out = msd(&exe, &["run", "paper.toml", "--quiet"], &lab);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("experiment `paper`"), "{stdout}");
    let folder = lab.join("msd-results").join("paper");
    assert!(stdout.contains("msd-results/paper/report.html"), "{stdout}");
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(folder.join("results.json")).unwrap())
            .unwrap();
    let report = std::fs::read_to_string(folder.join("report.md")).unwrap();
    assert!(
        report.contains("`msd run paper.toml`"),
        "the report names the command"
    );

    // `cargo xtask experiment` is the library's run with the workspace's results folder.
    let options = msd_experiment::RunOptions {
        results_root: Some(dir.path().join("xtask")),
        command: Some("cargo xtask experiment".into()),
        ..Default::default()
    };
    let library =
        msd_experiment::run_experiment(&workspace_config("paper.toml"), &options).unwrap();
    assert_eq!(library.out_dir, dir.path().join("xtask").join("paper"));
    let library: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(library.out_dir.join("results.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(stable(written), stable(library));
}

#[test]
fn help_names_the_run_command_and_bad_input_exits_2_writing_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let exe = installed();
    let help = msd(&exe, &["--help"], dir.path());
    assert!(help.status.success());
    assert!(String::from_utf8_lossy(&help.stdout).contains("msd run"));
    let run_help = msd(&exe, &["run", "--help"], dir.path());
    let text = String::from_utf8_lossy(&run_help.stdout);
    for fragment in [
        "--out",
        "--seed",
        "--threads",
        "--quiet",
        "msd-results",
        "Exit status",
    ] {
        assert!(text.contains(fragment), "{fragment} missing from:\n{text}");
    }

    std::fs::write(
        dir.path().join("bad.toml"),
        "name = \"bad\"\n[plant]\nmass = -1.0\n",
    )
    .unwrap();
    let out = msd(&exe, &["run", "bad.toml"], dir.path());
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("error: bad.toml"), "{err}");
    assert!(!dir.path().join("msd-results").exists());
}

/// `msd plan … | head -1`: a reader that closes its end before the plan is printed ends
/// the printing quietly (exit 0), not with a panic (exit 101) on the broken pipe.
#[test]
fn a_closed_stdout_is_not_a_panic() {
    let mut child = Command::new(installed())
        .args([
            "plan",
            workspace_config("paper-fast.toml").to_str().unwrap(),
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("msd runs");
    drop(child.stdout.take()); // the reader goes before the plan is computed
    let out = child.wait_with_output().expect("msd ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}
