//! A forward-looking camera on the car: renders the flat world of a [`RoadScene`] (and sky above
//! the horizon) as a pinhole camera sees it, at DAVE-2's input size (66 x 200).
//!
//! Frames are grayscale by default (the network's first convolution then costs a third of the
//! RGB one); [`Camera::render_rgb`] gives the same picture in colour for looking at (PNG). The
//! gray levels are the luma of the colours, so both show the same scene.
//!
//! Speed: the camera is fixed to the car, so each pixel's ground-plane hit point in the car's frame
//! is computed once ([`Camera::new`]); a frame transforms those points to the world and classifies
//! each by its distance to the road's centre line ([`RoadScene`]). Along an image row the ground
//! points are evenly spaced and the distance to the centre line is 1-Lipschitz, so after one exact
//! classification the pixels that cannot change class are filled without a search (exactly the
//! per-pixel result; a test checks it).
//!
//! Mounting (defaults, [`CameraParams`]): 1.5 m above the ground, 0.5 m ahead of the car's centre,
//! pitched 8° down, 75° horizontal field of view; rows 0–14 are sky and the nearest ground
//! seen is about 4 m ahead. Changing these changes every frame: weights trained on one camera
//! do not carry over to another.

use super::frame::Frame;
use super::scene::{RoadScene, Surface, GRAY, RGB};
use crate::road::Point;

/// DAVE-2's input height, pixels.
pub const FRAME_HEIGHT: usize = 66;
/// DAVE-2's input width, pixels.
pub const FRAME_WIDTH: usize = 200;

/// Where the camera sits on the car and what it sees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraParams {
    /// Image width, pixels.
    pub width: usize,
    /// Image height, pixels.
    pub height: usize,
    /// Horizontal field of view, degrees.
    pub hfov_deg: f64,
    /// Pitch below the horizontal, degrees.
    pub pitch_down_deg: f64,
    /// Height above the ground, metres.
    pub height_m: f64,
    /// Forward distance from the car's centre, metres.
    pub forward_m: f64,
    /// Sideways distance from the car's centre line, metres, positive left (side cameras).
    pub left_m: f64,
    /// Ground points farther ahead of the camera than this (metres) show as grass: a haze limit
    /// (whole image rows, so a row stays evenly spaced on the ground).
    pub max_range_m: f64,
}

impl Default for CameraParams {
    fn default() -> Self {
        Self {
            width: FRAME_WIDTH,
            height: FRAME_HEIGHT,
            hfov_deg: 75.0,
            pitch_down_deg: 8.0,
            height_m: 1.5,
            forward_m: 0.5,
            left_m: 0.0,
            max_range_m: 120.0,
        }
    }
}

/// A camera fixed to the car, with its per-pixel ground rays precomputed.
#[derive(Debug, Clone)]
pub struct Camera {
    params: CameraParams,
    /// Per pixel: the ground point in the car's frame `[forward, left]` metres, or NaN (sky).
    ground: Vec<[f64; 2]>,
}

impl Camera {
    /// A camera with `params`.
    pub fn new(params: CameraParams) -> Self {
        let (w, h) = (params.width, params.height);
        let focal = (w as f64 / 2.0) / (params.hfov_deg.to_radians() / 2.0).tan();
        let (sin_p, cos_p) = params.pitch_down_deg.to_radians().sin_cos();
        let mut ground = Vec::with_capacity(w * h);
        for r in 0..h {
            // Image coordinates from the optical centre: u right, v down, pixels.
            let v = r as f64 + 0.5 - h as f64 / 2.0;
            for c in 0..w {
                let u = c as f64 + 0.5 - w as f64 / 2.0;
                // Ray (car frame: forward, left, up) = focal·fwd + u·right + v·down with
                // fwd = (cos p, 0, −sin p), right = (0, −1, 0), down = (−sin p, 0, −cos p).
                let fwd = focal * cos_p - v * sin_p;
                let left = -u;
                let down = focal * sin_p + v * cos_p;
                let hit = if down > 0.0 {
                    let t = params.height_m / down;
                    let g = [params.forward_m + t * fwd, params.left_m + t * left];
                    if t * fwd <= params.max_range_m {
                        g
                    } else {
                        // Beyond the haze limit: ground far away, shown as grass.
                        [f64::INFINITY, 0.0]
                    }
                } else {
                    [f64::NAN, f64::NAN]
                };
                ground.push(hit);
            }
        }
        Self { params, ground }
    }

    /// The camera's parameters.
    pub fn params(&self) -> &CameraParams {
        &self.params
    }

    /// Classifies every pixel for a car at `position` heading `heading_rad` (counter-clockwise
    /// from east), calling `put(pixel_index, surface)`.
    fn classify(
        &self,
        scene: &RoadScene,
        position: Point,
        heading_rad: f64,
        mut put: impl FnMut(usize, Surface),
    ) {
        let (s, c) = heading_rad.sin_cos();
        let w = self.params.width;
        let world = |g: &[f64; 2]| {
            [
                position[0] + g[0] * c - g[1] * s,
                position[1] + g[0] * s + g[1] * c,
            ]
        };
        for (r, row) in self.ground.chunks_exact(w).enumerate() {
            if row[0][0].is_nan() || row[0][0].is_infinite() {
                let surface = if row[0][0].is_nan() {
                    Surface::Sky
                } else {
                    Surface::Grass
                };
                for i in r * w..(r + 1) * w {
                    put(i, surface);
                }
                continue;
            }
            // Ground points along a row are evenly spaced: `step` metres apart.
            let step = if w > 1 {
                (row[1][0] - row[0][0]).hypot(row[1][1] - row[0][1])
            } else {
                f64::INFINITY
            };
            let mut col = 0;
            while col < w {
                let (surface, margin) = scene.surface_and_margin(world(&row[col]));
                // Pixels within `margin` of this one show the same.
                let same = if step > 0.0 {
                    ((margin / step).floor() as usize).min(w - 1 - col)
                } else {
                    w - 1 - col
                };
                for i in col..=col + same {
                    put(r * w + i, surface);
                }
                col += same + 1;
            }
        }
    }

    /// The pixels of `out`, made this camera's size with `channels` channels if it is not.
    fn sized<'f>(&self, out: &'f mut Frame, channels: usize) -> &'f mut [u8] {
        let (w, h) = (self.params.width, self.params.height);
        if out.width != w || out.height != h || out.channels != channels {
            *out = Frame::new(w, h, channels);
        }
        &mut out.data
    }

    /// Renders the grayscale frame into `out` (resized if needed).
    pub fn render_into(
        &self,
        scene: &RoadScene,
        position: Point,
        heading_rad: f64,
        out: &mut Frame,
    ) {
        let data = self.sized(out, 1);
        self.classify(scene, position, heading_rad, |i, s| {
            data[i] = GRAY[s as usize];
        });
    }

    /// The grayscale frame for a car at `position` heading `heading_rad`.
    pub fn render(&self, scene: &RoadScene, position: Point, heading_rad: f64) -> Frame {
        let mut f = Frame::new(self.params.width, self.params.height, 1);
        self.render_into(scene, position, heading_rad, &mut f);
        f
    }

    /// The same picture in colour.
    pub fn render_rgb(&self, scene: &RoadScene, position: Point, heading_rad: f64) -> Frame {
        let mut f = Frame::new(self.params.width, self.params.height, 3);
        self.render_rgb_into(scene, position, heading_rad, &mut f);
        f
    }

    /// Renders the colour frame into `out` (resized if needed).
    pub fn render_rgb_into(
        &self,
        scene: &RoadScene,
        position: Point,
        heading_rad: f64,
        out: &mut Frame,
    ) {
        let data = self.sized(out, 3);
        self.classify(scene, position, heading_rad, |i, s| {
            data[3 * i..3 * i + 3].copy_from_slice(&RGB[s as usize]);
        });
    }
}

impl Default for Camera {
    fn default() -> Self {
        Self::new(CameraParams::default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::road::{Road, LANE_WIDTH_M};
    use crate::vision::scene::{EDGE_LINE_INSET_M, LINE_WIDTH_M};
    use crate::vision::write_png;

    fn straight_road() -> Road {
        let pts: Vec<Point> = (0..=12).map(|i| [100.0, 10.0 + 15.0 * i as f64]).collect();
        Road::new(&pts).unwrap()
    }

    /// Columns of `surface` pixels in row `r`.
    fn columns_of(
        scene: &RoadScene,
        cam: &Camera,
        pos: Point,
        heading: f64,
        r: usize,
        s: Surface,
    ) -> Vec<usize> {
        let f = cam.render(scene, pos, heading);
        (0..f.width)
            .filter(|&c| f.get(r, c, 0) == GRAY[s as usize])
            .collect()
    }

    #[test]
    fn straight_road_from_the_lane_centre() {
        let road = straight_road();
        let scene = RoadScene::new(&road);
        let cam = Camera::default();
        // Right lane centre, heading north.
        let pos = [102.0, 40.0];
        let heading = std::f64::consts::FRAC_PI_2;
        let f = cam.render(&scene, pos, heading);
        // The top rows are sky, the bottom row ground.
        let sky = |r: usize| (0..f.width).all(|c| f.get(r, c, 0) == GRAY[Surface::Sky as usize]);
        assert!((0..=14).all(sky) && !sky(15));
        let mid = f.width / 2;
        for r in [45, 55, 65] {
            let yellow = columns_of(&scene, &cam, pos, heading, r, Surface::Yellow);
            let white = columns_of(&scene, &cam, pos, heading, r, Surface::White);
            assert!(!yellow.is_empty(), "row {r}: no yellow");
            assert!(
                yellow.iter().all(|&c| c < mid),
                "row {r}: yellow {yellow:?}"
            );
            let right: Vec<usize> = white.iter().copied().filter(|&c| c >= mid).collect();
            assert!(
                !right.is_empty(),
                "row {r}: no white right of centre {white:?}"
            );
            // Symmetric: on a ground row, image offsets are proportional to lateral offsets;
            // the yellow line is 2 m left of the car, the right edge line's middle
            // 2 m − inset − half a line width right of it.
            let ly = mid as f64 - yellow.iter().sum::<usize>() as f64 / yellow.len() as f64;
            let rw = right.iter().sum::<usize>() as f64 / right.len() as f64 - mid as f64;
            let white_m = LANE_WIDTH_M / 2.0 - EDGE_LINE_INSET_M - LINE_WIDTH_M / 2.0;
            let ratio = (ly / (LANE_WIDTH_M / 2.0)) / (rw / white_m);
            assert!((ratio - 1.0).abs() < 0.06, "row {r}: {ly} vs {rw}");
        }
        // Grass at the bottom corners is impossible this close; asphalt under the car.
        assert_eq!(f.get(65, mid, 0), GRAY[Surface::Asphalt as usize]);
    }

    #[test]
    fn frames_are_deterministic_and_rgb_matches_gray() {
        let road = straight_road();
        let scene = RoadScene::new(&road);
        let cam = Camera::default();
        let a = cam.render(&scene, [101.3, 50.0], 1.4);
        let b = cam.render(&scene, [101.3, 50.0], 1.4);
        assert_eq!(a, b);
        let rgb = cam.render_rgb(&scene, [101.3, 50.0], 1.4);
        for i in 0..a.data.len() {
            let k = GRAY.iter().position(|&g| g == a.data[i]).unwrap();
            assert_eq!(&rgb.data[3 * i..3 * i + 3], &RGB[k]);
        }
    }

    #[test]
    fn skipping_matches_per_pixel_classification() {
        let pts: Vec<Point> = vec![[100.0, 10.0], [100.0, 40.0], [120.0, 70.0], [150.0, 80.0]];
        let road = Road::new(&pts).unwrap();
        let scene = RoadScene::new(&road);
        let cam = Camera::default();
        for (pos, heading) in [
            ([102.0, 20.0], 1.5),
            ([101.0, 12.0], 1.6),
            ([99.0, 8.0], 1.2),
            ([130.0, 78.0], 0.1),
            ([148.0, 80.0], 0.3),
            ([110.0, 60.0], -2.0),
        ] {
            let f = cam.render(&scene, pos, heading);
            let (s, c) = f64::sin_cos(heading);
            for (i, g) in cam.ground.iter().enumerate() {
                let want = if g[0].is_nan() {
                    Surface::Sky
                } else if g[0].is_infinite() {
                    Surface::Grass
                } else {
                    scene.surface([pos[0] + g[0] * c - g[1] * s, pos[1] + g[0] * s + g[1] * c])
                };
                assert_eq!(f.data[i], GRAY[want as usize], "{pos:?} pixel {i}");
            }
        }
    }

    #[test]
    fn png_round_trips() {
        let road = straight_road();
        let scene = RoadScene::new(&road);
        let cam = Camera::default();
        let dir = std::env::temp_dir();
        for (name, frame) in [
            ("gray", cam.render(&scene, [102.0, 30.0], 1.5)),
            ("rgb", cam.render_rgb(&scene, [102.0, 30.0], 1.5)),
        ] {
            let path = dir.join(format!("road-sim-camera-{}-{name}.png", std::process::id()));
            write_png(&path, &frame).unwrap();
            let decoder =
                png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
            let mut reader = decoder.read_info().unwrap();
            let mut buf = vec![0; reader.output_buffer_size().unwrap()];
            let info = reader.next_frame(&mut buf).unwrap();
            std::fs::remove_file(&path).unwrap();
            assert_eq!((info.width, info.height), (200, 66));
            assert_eq!(&buf[..info.buffer_size()], &frame.data[..]);
        }
    }

    #[test]
    #[ignore = "writes PNGs to target/ for a look"]
    fn write_sample_pngs() {
        let pts: Vec<Point> = vec![[100.0, 10.0], [100.0, 40.0], [120.0, 70.0], [150.0, 80.0]];
        let road = Road::new(&pts).unwrap();
        let scene = RoadScene::new(&road);
        let cam = Camera::default();
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target");
        let f = cam.render_rgb(&scene, [102.0, 20.0], std::f64::consts::FRAC_PI_2);
        write_png(&dir.join("camera_rgb.png"), &f).unwrap();
        let f = cam.render(&scene, [102.0, 20.0], std::f64::consts::FRAC_PI_2);
        write_png(&dir.join("camera_gray.png"), &f).unwrap();
    }
}
