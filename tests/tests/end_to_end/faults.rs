//! Faults while a run writes its results: an output folder that cannot be created, a
//! full disk, a failed final move, a panic and a killed process. Each ends in a clear
//! error (exit status 1) or, for a kill, in leftovers the next run cleans up; never in a
//! partial output folder, and a previous result survives every one of them.

use msd_experiment::output::{Fault, MARKER, inject_fault};
use msd_experiment::{ExperimentError, RunOptions, run_experiment};
use msd_tests::{TINY_CONFIG, listing};
use std::path::{Path, PathBuf};

/// A scratch folder with the tiny config in it; runs write to `<dir>/out`.
struct Case {
    dir: tempfile::TempDir,
}

impl Case {
    fn new() -> Self {
        let dir = tempfile::tempdir().expect("a temporary folder");
        std::fs::write(dir.path().join("tiny.toml"), TINY_CONFIG).expect("the config");
        Self { dir }
    }

    fn out(&self) -> PathBuf {
        self.dir.path().join("out")
    }

    fn run_into(&self, out: &Path) -> Result<msd_experiment::RunSummary, ExperimentError> {
        let options = RunOptions {
            out: Some(out.to_path_buf()),
            ..RunOptions::default()
        };
        run_experiment(&self.dir.path().join("tiny.toml"), &options)
    }

    fn run(&self) -> Result<msd_experiment::RunSummary, ExperimentError> {
        self.run_into(&self.out())
    }

    /// A previous, complete result in `out/`.
    /// A previous result: a folder with the marker a run writes.
    fn previous_result(&self) {
        std::fs::create_dir(self.out()).unwrap();
        std::fs::write(self.out().join(MARKER), "").unwrap();
        std::fs::write(self.out().join("results.json"), "{\"previous\": true}\n").unwrap();
    }

    fn previous_result_is_intact(&self) {
        assert_eq!(
            std::fs::read_to_string(self.out().join("results.json")).unwrap(),
            "{\"previous\": true}\n"
        );
        assert_eq!(listing(&self.out()), [MARKER, "results.json"]);
    }
}

/// A run failure: exit status 1, one line starting with the stage, containing
/// `fragments`.
fn assert_run_failure(err: &ExperimentError, fragments: &[&str]) {
    assert_eq!(err.exit_code(), 1, "{err}");
    let message = err.to_string();
    assert!(!message.contains('\n'), "one line: {message}");
    assert!(message.starts_with("write failed: "), "{message}");
    for fragment in fragments {
        assert!(message.contains(fragment), "`{message}` lacks `{fragment}`");
    }
}

/// The lab template's folder used as the output: the measurement, the config and the
/// notes must survive. The run is refused before anything is computed (exit 2, naming
/// the folder and what to do), and nothing in the folder changes.
#[test]
fn a_folder_of_the_users_files_is_never_replaced() {
    let case = Case::new();
    let folder = case.dir.path().join("lab");
    std::fs::create_dir(&folder).unwrap();
    for (name, text) in [("measurement.csv", "t,force,x\n"), ("notes.txt", "rig 3\n")] {
        std::fs::write(folder.join(name), text).unwrap();
    }
    std::fs::copy(
        case.dir.path().join("tiny.toml"),
        folder.join("experiment.toml"),
    )
    .unwrap();
    let err = case
        .run_into(&folder)
        .expect_err("the folder holds the user's files");
    assert_eq!(err.exit_code(), 2, "{err}");
    let message = err.to_string();
    for fragment in [
        "lab",
        "experiment.toml, measurement.csv, notes.txt",
        "--out",
    ] {
        assert!(message.contains(fragment), "`{message}` lacks `{fragment}`");
    }
    assert_eq!(
        listing(&folder),
        ["experiment.toml", "measurement.csv", "notes.txt"]
    );
    assert_eq!(listing(case.dir.path()), ["lab", "tiny.toml"]);

    // A previous result (its marker) is replaced as before, and so is an empty folder.
    let empty = case.dir.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    case.run_into(&empty).expect("an empty folder is used");
    assert!(listing(&empty).contains(&MARKER.to_string()));
    case.run_into(&empty)
        .expect("a previous result is replaced");
    // A result written before the marker existed holds only files runs write.
    let legacy = case.dir.path().join("legacy");
    std::fs::create_dir(&legacy).unwrap();
    for name in ["results.json", "report.md", "fig3_validation.svg"] {
        std::fs::write(legacy.join(name), "").unwrap();
    }
    case.run_into(&legacy).expect("an old result is replaced");
    std::fs::write(legacy.join("my-notes.md"), "").unwrap();
    std::fs::remove_file(legacy.join(MARKER)).unwrap();
    let err = case
        .run_into(&legacy)
        .expect_err("notes added to an old result");
    assert!(err.to_string().contains("my-notes.md"), "{err}");
}

#[test]
fn an_output_folder_below_a_file_cannot_be_created() {
    let case = Case::new();
    std::fs::write(case.dir.path().join("file.txt"), "not a folder").unwrap();
    let out = case.dir.path().join("file.txt").join("out");
    let err = case.run_into(&out).expect_err("a folder inside a file");
    assert_run_failure(&err, &["cannot create the parent of", "file.txt/out"]);
    assert_eq!(listing(case.dir.path()), ["file.txt", "tiny.toml"]);
}

#[test]
fn an_output_path_that_is_a_file_is_refused() {
    let case = Case::new();
    std::fs::write(case.out(), "a file").unwrap();
    let err = case.run().expect_err("the target is a file");
    assert_eq!(err.exit_code(), 2, "{err}");
    assert!(
        err.to_string().contains("exists and is not a folder"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(case.out()).unwrap(), "a file");
    assert_eq!(listing(case.dir.path()), ["out", "tiny.toml"]);
}

/// /proc accepts no new folders, not even from root (CI containers often run as root,
/// where permission bits do not stop a write).
#[cfg(target_os = "linux")]
#[test]
fn an_output_folder_on_a_read_only_file_system_cannot_be_created() {
    let case = Case::new();
    let out = Path::new("/proc/msd-toolkit-test/out");
    let err = case.run_into(out).expect_err("/proc is not writable");
    assert_run_failure(
        &err,
        &["cannot create the parent of", "/proc/msd-toolkit-test/out"],
    );
    assert!(!out.exists());
    assert_eq!(listing(case.dir.path()), ["tiny.toml"]);
}

/// A folder without write permission: refused, unless this process may write anyway
/// (root), which is then checked and reported instead.
#[cfg(unix)]
#[test]
fn a_read_only_parent_folder() {
    use std::os::unix::fs::PermissionsExt;
    let case = Case::new();
    let locked = case.dir.path().join("locked");
    std::fs::create_dir(&locked).unwrap();
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o555)).unwrap();
    let root_like = std::fs::write(locked.join("probe"), "").is_ok();
    let result = case.run_into(&locked.join("out"));
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o755)).unwrap();
    if root_like {
        // Permission bits do not bind this user: the run must simply succeed.
        std::fs::remove_file(locked.join("probe")).unwrap();
        result.expect("a writable folder for this user");
        assert_eq!(listing(&locked), ["out"]);
    } else {
        let err = result.expect_err("a read-only folder");
        assert_run_failure(
            &err,
            &["cannot create a staging folder for", "Permission denied"],
        );
        assert!(listing(&locked).is_empty(), "{:?}", listing(&locked));
    }
}

/// The disk fills up while writing: at the first CSV file (the figures are already in
/// the staging folder) and at results.json, the very last file. Half of the file is
/// on disk when the write fails; all of it disappears.
#[test]
fn a_full_disk_midway_leaves_nothing() {
    for file in ["identification.csv", "results.json"] {
        let case = Case::new();
        let err = {
            let _fault = inject_fault(Fault::DiskFull { file: file.into() });
            case.run().expect_err("the disk is full")
        };
        assert_run_failure(
            &err,
            &[&format!("cannot write {file}"), "No space left on device"],
        );
        assert_eq!(listing(case.dir.path()), ["tiny.toml"], "{file}");
    }
}

#[test]
fn a_full_disk_leaves_a_previous_result_untouched() {
    let case = Case::new();
    case.previous_result();
    let err = {
        let _fault = inject_fault(Fault::DiskFull {
            file: "results.json".into(),
        });
        case.run().expect_err("the disk is full")
    };
    assert_run_failure(&err, &["cannot write results.json"]);
    case.previous_result_is_intact();
    assert_eq!(listing(case.dir.path()), ["out", "tiny.toml"]);
}

/// The last step, moving the finished folder onto the target, fails after the previous
/// result was moved aside: the previous result is put back.
#[test]
fn a_failed_final_move_puts_the_previous_result_back() {
    let case = Case::new();
    case.previous_result();
    let err = {
        let _fault = inject_fault(Fault::Commit);
        case.run().expect_err("the move fails")
    };
    assert_run_failure(&err, &["cannot move the results into", "out"]);
    case.previous_result_is_intact();
    assert_eq!(listing(case.dir.path()), ["out", "tiny.toml"]);
    // Without a previous result the same failure leaves no folder at all.
    let fresh = Case::new();
    let err = {
        let _fault = inject_fault(Fault::Commit);
        fresh.run().expect_err("the move fails")
    };
    assert_run_failure(&err, &["cannot move the results into"]);
    assert_eq!(listing(fresh.dir.path()), ["tiny.toml"]);
}

/// A panic while writing unwinds through the run; the staging folder is removed on
/// the way out.
#[test]
fn a_panic_while_writing_leaves_nothing() {
    let case = Case::new();
    case.previous_result();
    let outcome = std::panic::catch_unwind(|| {
        let _fault = inject_fault(Fault::Panic {
            file: "report.md".into(),
        });
        case.run()
    });
    let payload = outcome.expect_err("the injected panic unwinds");
    let message = payload
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_default();
    assert!(message.contains("report.md"), "{message}");
    case.previous_result_is_intact();
    assert_eq!(listing(case.dir.path()), ["out", "tiny.toml"]);
}

/// The id of a process that has ended.
fn dead_pid() -> u32 {
    let mut child = std::process::Command::new("true")
        .spawn()
        .expect("`true` runs");
    let pid = child.id();
    child.wait().expect("`true` ends");
    pid
}

/// The child half of `a_killed_run_leaves_only_hidden_leftovers_that_the_next_run_removes`:
/// a no-op unless that test starts this binary with `MSD_TESTS_KILL_INTO` set.
#[test]
fn killed_run_child() {
    let Some(out) = std::env::var_os("MSD_TESTS_KILL_INTO") else {
        return;
    };
    let out = PathBuf::from(out);
    let config = out.parent().expect("a parent").join("tiny.toml");
    let _fault = inject_fault(Fault::Kill {
        file: "results.json".into(),
    });
    let options = RunOptions {
        out: Some(out),
        ..RunOptions::default()
    };
    let _ = run_experiment(&config, &options);
    unreachable!("the injected kill ends the process");
}

/// A process killed while writing (here: ended halfway through results.json without
/// running any destructor, as `kill -9` or a power cut would) cannot clean up. Its target is
/// untouched: only a hidden staging folder is left. The next run into the same target
/// removes it and succeeds.
#[cfg(target_os = "linux")]
#[test]
fn a_killed_run_leaves_only_hidden_leftovers_that_the_next_run_removes() {
    let case = Case::new();
    case.previous_result();
    let status = std::process::Command::new(std::env::current_exe().unwrap())
        .args(["faults::killed_run_child", "--exact", "--test-threads=1"])
        .env("MSD_TESTS_KILL_INTO", case.out())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .expect("the test binary runs");
    assert_eq!(
        status.code(),
        Some(137),
        "the child was meant to be killed: {status}"
    );
    case.previous_result_is_intact();
    let left = listing(case.dir.path());
    assert_eq!(left.len(), 3, "{left:?}");
    let staging = left
        .iter()
        .find(|n| n.starts_with(".out.partial-"))
        .unwrap_or_else(|| panic!("a staging folder is left: {left:?}"));
    let leftover = listing(&case.dir.path().join(staging));
    assert!(
        leftover.contains(&"results.json".to_string()),
        "{leftover:?}"
    );

    let run = case.run().expect("the next run succeeds");
    assert_eq!(listing(case.dir.path()), ["out", "tiny.toml"]);
    msd_tests::assert_results_file_is(&case.out(), &run.results);
}

/// A kill between moving the previous result aside and moving the new one in leaves
/// the previous result as `.out.old-<pid>`: the next run puts it back before it starts,
/// so even when that run fails the previous result is where it was.
#[cfg(target_os = "linux")]
#[test]
fn a_previous_result_left_aside_by_a_kill_is_put_back() {
    let case = Case::new();
    let aside = case.dir.path().join(format!(".out.old-{}", dead_pid()));
    std::fs::create_dir(&aside).unwrap();
    std::fs::write(aside.join(MARKER), "").unwrap();
    std::fs::write(aside.join("results.json"), "{\"previous\": true}\n").unwrap();
    let err = {
        let _fault = inject_fault(Fault::DiskFull {
            file: "results.json".into(),
        });
        case.run().expect_err("the disk is full")
    };
    assert_run_failure(&err, &["No space left on device"]);
    case.previous_result_is_intact();
    assert_eq!(listing(case.dir.path()), ["out", "tiny.toml"]);
}

/// Leftovers of a process that still runs (another run into the same folder) are not
/// touched.
#[cfg(target_os = "linux")]
#[test]
fn staging_folders_of_running_processes_are_left_alone() {
    let case = Case::new();
    let mut sleeper = std::process::Command::new("sleep")
        .arg("30")
        .spawn()
        .expect("`sleep` runs");
    let busy = case
        .dir
        .path()
        .join(format!(".out.partial-{}-1", sleeper.id()));
    std::fs::create_dir(&busy).unwrap();
    let dead = case
        .dir
        .path()
        .join(format!(".out.partial-{}-1", dead_pid()));
    std::fs::create_dir(&dead).unwrap();
    let result = case.run();
    sleeper.kill().expect("sleep stops");
    sleeper.wait().expect("sleep ends");
    result.expect("the run succeeds");
    assert!(
        busy.exists(),
        "a running process's staging folder was removed"
    );
    assert!(!dead.exists(), "a dead process's staging folder was kept");
}
