//! Helpers shared by the end-to-end tests: run the binary, read its JSON lines.

use serde_json::Value;
use std::io::Write;
use std::path::PathBuf;
use std::process::{Child, Command, Output, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// A fresh, empty scratch directory for one test (each test binary is its own process, so the
/// process id keeps binaries apart and `name` keeps tests apart).
pub fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("wogan-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

/// Writes `text` to `dir/name` and returns the path as an argument for the binary.
pub fn write_file(dir: &std::path::Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("a scratch file");
    path.to_str().expect("a UTF-8 path").to_owned()
}

/// Runs `wogan ARGS` with `stdin` as its standard input and waits for it.
pub fn wogan(args: &[&str], stdin: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_wogan"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("wogan starts");
    // Written from another thread: the commands answer as they read, so a large input written
    // before any output is read would fill both pipes and deadlock.
    let mut input = child.stdin.take().expect("stdin is piped");
    let bytes = stdin.as_bytes().to_vec();
    let writer = std::thread::spawn(move || {
        // A command may end before reading all of it (bad usage): that is not the test's failure.
        let _ = input.write_all(&bytes);
    });
    let output = child.wait_with_output().expect("wogan ends");
    writer.join().expect("the input writer ends");
    output
}

/// Runs `wogan ARGS` like [`wogan`] and asserts that it succeeded, showing its standard error if not.
pub fn wogan_ok(args: &[&str], stdin: &str) -> Output {
    let output = wogan(args, stdin);
    assert_eq!(
        output.status.code(),
        Some(0),
        "wogan {args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

/// The JSON lines a command wrote to standard output.
pub fn records(output: &Output) -> Vec<Value> {
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).expect("every output line is JSON"))
        .collect()
}

/// Kills `child` if the test has not finished within `limit` (a hang detector, not a timing).
pub fn watchdog(child: &Child, limit: Duration) -> Arc<AtomicBool> {
    let done = Arc::new(AtomicBool::new(false));
    let (pid, flag) = (child.id(), Arc::clone(&done));
    std::thread::spawn(move || {
        let step = Duration::from_millis(200);
        let mut waited = Duration::ZERO;
        while waited < limit {
            if flag.load(Ordering::SeqCst) {
                return;
            }
            std::thread::sleep(step);
            waited += step;
        }
        let _ = Command::new("kill")
            .args(["-KILL", &pid.to_string()])
            .status();
    });
    done
}

/// Sends `signal` (`-TERM`, `-INT`) to `child` and waits for it: its exit status and its stderr.
/// `done` (its watchdog's flag) is set once it has ended.
pub fn signal_and_wait(
    child: &mut Child,
    signal: &str,
    done: &AtomicBool,
) -> (std::process::ExitStatus, String) {
    Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .expect("kill");
    let mut stderr = String::new();
    std::io::Read::read_to_string(
        &mut std::io::BufReader::new(child.stderr.take().expect("piped stderr")),
        &mut stderr,
    )
    .expect("stderr");
    let status = child.wait().expect("the child ends");
    done.store(true, Ordering::SeqCst);
    (status, stderr)
}

/// The test records of a run file (none when it does not exist yet).
pub fn test_records(path: &std::path::Path) -> Vec<Value> {
    std::fs::read_to_string(path)
        .unwrap_or_default()
        .lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .filter(|r| r["type"] == "test")
        .collect()
}

/// Starts `wogan ARGS` with every standard stream piped.
pub fn spawn(args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_wogan"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("wogan starts")
}

/// Runs `tests/python/SCRIPT --wogan BINARY` and asserts that it passed; where python3 is missing
/// (it is not a build dependency) it says so and checks nothing.
pub fn python_check(script: &str) {
    let repo = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let Ok(output) = Command::new("python3")
        .arg(format!("{repo}/tests/python/{script}"))
        .args(["--wogan", env!("CARGO_BIN_EXE_wogan")])
        .output()
    else {
        eprintln!("python3 is not available: {script} was not run");
        return;
    };
    assert!(
        output.status.success(),
        "{script}: {}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}

/// The names of the entries of `dir`, sorted.
pub fn entry_names(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| {
            entry
                .expect("an entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.sort();
    names
}

/// The Python of the venv `examples/EXAMPLE/setup.sh` makes (`target/VENV/bin/python`), or `None`,
/// said so, when it is missing: a dependency that is not the build's. Where the environment
/// variable `require` is set (CI sets it after running the setup) a missing venv fails the test.
pub fn venv_python(venv: &str, setup: &str, require: &str) -> Option<PathBuf> {
    let python = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../target"))
        .join(venv)
        .join("bin/python");
    if python.exists() {
        return Some(python);
    }
    assert!(
        std::env::var_os(require).is_none(),
        "{require} is set but {} is missing: run {setup}",
        python.display()
    );
    eprintln!(
        "no {} ({setup} makes it): the test is skipped",
        python.display()
    );
    None
}
