//! Roads read from input as every command reads them: road-sim's forms, with the objects that
//! hold no road passed over, namely wogan's own records (so that a run file pipes into `simulate`)
//! and the executor protocol's `hello` and `bye` (so that `wogan simulate` serves as an executor).

use super::json_lines::numbered_lines;
use anyhow::{Context, Result};
use road_sim::road::{Point, RoadInput, RoadReader};
use std::io::BufRead;
use std::path::Path;

/// Object types that hold no road: the records of [`super::records`] without one, and the
/// executor protocol's `hello` and `bye` (`crate::sut::executor_protocol`, whose test checks that
/// they are here).
pub const PASSED_OVER: [&str; 7] = [
    "header", "train", "summary", "error", "verdict", "hello", "bye",
];

/// The reader every command reads roads with, on a map of `map_size_m`.
pub fn road_reader(map_size_m: f64) -> RoadReader<'static> {
    RoadReader {
        map_size_m,
        passed_over: &PASSED_OVER,
    }
}

/// The roads of `input`, in order, each with its line number; lines that hold no road are passed
/// over. A line that cannot be read or holds a bad road is an error naming the line (and `path`,
/// when the input is a file).
pub fn roads_of_lines<'a>(
    input: Box<dyn BufRead + Send>,
    map_size_m: f64,
    path: Option<&'a Path>,
) -> impl Iterator<Item = Result<(usize, Vec<Point>)>> + 'a {
    let reader = road_reader(map_size_m);
    let place = move |number: usize| match path {
        Some(path) => format!("{}: line {number}", path.display()),
        None => format!("line {number}"),
    };
    numbered_lines(input).filter_map(move |line| {
        let line = match line {
            Ok(line) => line,
            Err(error) => return Some(Err(error.into())),
        };
        let road = line
            .text
            .map_err(anyhow::Error::msg)
            .and_then(|text| Ok(reader.read_line(&text)?))
            .with_context(|| place(line.number));
        match road {
            Ok(RoadInput::Skip) => None,
            Ok(road) => Some(Ok((
                line.number,
                road.points().unwrap_or_default().to_vec(),
            ))),
            Err(error) => Some(Err(error)),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn roads_of(text: &'static str) -> Vec<Result<(usize, Vec<Point>)>> {
        roads_of_lines(
            Box::new(text.as_bytes()),
            200.0,
            Some(Path::new("in.jsonl")),
        )
        .collect()
    }

    #[test]
    fn records_without_a_road_are_passed_over_and_roads_keep_their_line() {
        let roads = roads_of(
            "{\"type\": \"header\"}\n[[0, 0], [0, 10]]\n{\"type\": \"hello\"}\n\
             {\"type\": \"test\", \"road_points\": [[1, 1], [1, 9]]}\n",
        );
        let roads: Vec<_> = roads.into_iter().map(Result::unwrap).collect();
        assert_eq!(
            roads,
            vec![
                (2, vec![[0.0, 0.0], [0.0, 10.0]]),
                (4, vec![[1.0, 1.0], [1.0, 9.0]])
            ]
        );
    }

    #[test]
    fn a_bad_line_is_an_error_naming_the_file_and_line() {
        let roads = roads_of("[[0, 0], [0, 10]]\n{\"road_points\": 3}\n");
        let error = roads[1].as_ref().unwrap_err();
        let message = format!("{error:#}");
        assert!(
            message.starts_with("in.jsonl: line 2: road_points"),
            "{message}"
        );
    }
}
