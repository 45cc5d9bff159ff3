//! Latency of `wogan simulate` and `wogan validate` as a streaming filter: one child process, one
//! road written at a time, the time from writing a line to reading its answer. Prints the median
//! and the slowest of 50 round trips per command and driver.
//!
//! `cargo bench -p wogan-cli --bench streaming`

use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};
use std::time::Instant;

const ROUND_TRIPS: usize = 50;

fn main() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/reference/roads.jsonl"
    );
    let roads: Vec<String> = std::fs::read_to_string(path)
        .expect("tests/reference/roads.jsonl")
        .lines()
        .take(ROUND_TRIPS)
        .map(str::to_owned)
        .collect();
    for args in [
        vec!["validate"],
        vec!["simulate", "--oracle", "beamng-ai-proxy"],
        vec!["simulate", "--oracle", "dave2-proxy"],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_wogan"))
            .args(&args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .expect("wogan starts");
        let mut stdin = child.stdin.take().expect("piped");
        let mut stdout = BufReader::new(child.stdout.take().expect("piped"));
        let mut latencies_ms = Vec::new();
        for road in &roads {
            let started = Instant::now();
            writeln!(stdin, "{road}").expect("written");
            stdin.flush().expect("flushed");
            let mut answer = String::new();
            stdout.read_line(&mut answer).expect("an answer");
            latencies_ms.push(started.elapsed().as_secs_f64() * 1e3);
        }
        drop(stdin);
        child.wait().expect("wogan ends");
        latencies_ms.sort_by(f64::total_cmp);
        println!(
            "wogan {}: line in to answer out, median {:.2} ms, slowest {:.2} ms ({ROUND_TRIPS} roads)",
            args.join(" "),
            latencies_ms[ROUND_TRIPS / 2],
            latencies_ms[ROUND_TRIPS - 1]
        );
    }
}
