//! The loop shared by the commands that answer one record per input road: read numbered lines,
//! parse each as a road, answer the roads (in parallel when asked), and write the answers in input
//! order, each flushed as soon as its chunk is done.

use crate::json_lines::{numbered_lines, InputLine, JsonLinesWriter};
use crate::records::{ErrorRecord, Record};
use crate::Status;
use anyhow::Result;
use rayon::prelude::*;
use road_sim::road::input::{parse_line, RoadInput};
use std::io::BufRead;

/// Roads answered together before their answers are written: large enough to keep every thread
/// busy, small enough that results stream.
const CHUNK_LINES: usize = 256;

/// Answers every road of `input` with `answer(line_number, road)`; a line that holds no road gets
/// an `error` record and makes the status [`Status::SomeLinesBad`].
pub fn answer_each_road<F>(
    input: Box<dyn BufRead>,
    out: &mut JsonLinesWriter,
    map_size_m: f64,
    pool: Option<&rayon::ThreadPool>,
    answer: F,
) -> Result<Status>
where
    F: Fn(usize, &RoadInput) -> Record + Sync,
{
    let mut status = Status::AllRead;
    let mut lines = numbered_lines(input).peekable();
    // Each line is parsed, answered and encoded by the worker that takes it; only reading and
    // writing stay on this thread.
    let run_one = |line: &InputLine| -> Option<Result<Vec<u8>, String>> {
        let text = match &line.text {
            Ok(text) => text,
            Err(error) => return Some(Err(error.clone())),
        };
        match parse_line(text, map_size_m) {
            Ok(RoadInput::Skip) => None,
            Ok(road) => Some(
                serde_json::to_vec(&answer(line.number, &road))
                    .map_err(|e| format!("cannot encode the answer: {e}")),
            ),
            Err(error) => Some(Err(error.to_string())),
        }
    };
    while lines.peek().is_some() {
        let chunk = lines
            .by_ref()
            .take(CHUNK_LINES)
            .collect::<Result<Vec<InputLine>, _>>()?;
        let answers: Vec<Option<Result<Vec<u8>, String>>> = match pool {
            Some(pool) => pool.install(|| chunk.par_iter().map(run_one).collect()),
            None => chunk.iter().map(run_one).collect(),
        };
        for (line, answer) in chunk.iter().zip(answers) {
            match answer {
                None => {}
                Some(Ok(encoded)) => out.write_encoded(encoded)?,
                Some(Err(error)) => {
                    status = Status::SomeLinesBad;
                    out.write(&Record::Error(ErrorRecord {
                        line: line.number,
                        error,
                    }))?;
                }
            }
        }
    }
    Ok(status)
}

/// A thread pool of `jobs` threads, or `None` for one job (answers on this thread).
pub fn thread_pool(jobs: usize) -> Result<Option<rayon::ThreadPool>> {
    if jobs <= 1 {
        return Ok(None);
    }
    let pool = rayon::ThreadPoolBuilder::new().num_threads(jobs).build()?;
    Ok(Some(pool))
}
