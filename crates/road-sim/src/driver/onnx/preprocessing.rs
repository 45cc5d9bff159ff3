//! From the camera's frame to the model's input tensor, as the competition's DAVE-2 executor
//! prepares its camera image (`self_driving/image_processing.py` of se2p/tool-competition-av): crop
//! rows off the top and bottom, resize to the model's size (bilinear: OpenCV's default, the
//! interpolation the competition's call ends up with, in OpenCV's fixed point), convert RGB to
//! YUV (OpenCV's 8-bit conversion), then scale the bytes as the model expects and lay them out
//! NCHW or NHWC. Both agree byte for byte with the competition's code and the Udacity course's
//! (whose crop leaves 75 of 320 x 160 and whose resize shrinks both ways, to 200 x 66) run with
//! OpenCV (vectors in tests/reference/dave2_contract.json and udacity_contract.json).
//!
//! The competition feeds the bytes unscaled (its Keras model normalises inside the graph), so
//! [`PixelScaling::Raw`] is the default. A 1-channel model sees the camera's gray frame (the luma
//! of its colours), cropped and resized the same way.

use super::model::{InputShape, Layout};
use crate::vision::Frame;
use serde::{Deserialize, Serialize};

/// How pixel bytes become the model's input values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PixelScaling {
    /// 0..255 as they are (the competition's: its model scales inside).
    #[default]
    Raw,
    /// `x / 255`, 0..1.
    Unit,
    /// `x / 127.5 - 1`, -1..1 (DAVE-2's normalisation).
    Symmetric,
}

impl PixelScaling {
    fn apply(self, v: u8) -> f32 {
        let v = f32::from(v);
        match self {
            PixelScaling::Raw => v,
            PixelScaling::Unit => v / 255.0,
            PixelScaling::Symmetric => v / 127.5 - 1.0,
        }
    }
}

/// What a 3-channel model's channels hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ColourSpace {
    /// Y, U, V (OpenCV's `COLOR_RGB2YUV`; the competition's).
    #[default]
    Yuv,
    /// R, G, B as the camera renders them.
    Rgb,
}

/// RGB bytes to YUV bytes as OpenCV converts 8-bit images (`COLOR_RGB2YUV`: BT.601 luma, U and
/// V scaled by 0.492 and 0.877 about 128, in 14-bit fixed point, rounded and saturated).
pub fn rgb_to_yuv([r, g, b]: [u8; 3]) -> [u8; 3] {
    const SHIFT: i32 = 14;
    const HALF: i32 = 1 << (SHIFT - 1);
    let (r, g, b) = (i32::from(r), i32::from(g), i32::from(b));
    let y = (r * 4899 + g * 9617 + b * 1868 + HALF) >> SHIFT;
    let chroma = |d: i32, k: i32| ((d * k + (128 << SHIFT) + HALF) >> SHIFT).clamp(0, 255) as u8;
    [y as u8, chroma(b - y, 8061), chroma(r - y, 14369)]
}

/// One output row or column of the resize: two source rows (columns) and their weights in
/// 2048ths.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Blend {
    first: usize,
    second: usize,
    weights: [i32; 2],
}

/// The preparation of frames for one model: crop, resize, colour, scaling, layout.
#[derive(Debug, Clone)]
pub struct Preprocessor {
    shape: InputShape,
    /// The camera frame's width and height, pixels.
    frame_size: [usize; 2],
    crop_top: usize,
    colour: ColourSpace,
    scaling: PixelScaling,
    /// Per output row and column, where it comes from in the cropped frame (both empty: the
    /// cropped frame is the model's size, no resize).
    rows: Vec<Blend>,
    columns: Vec<Blend>,
    /// A cropped row resized across, in 2048ths (OpenCV's horizontal pass), per source row.
    across: Vec<Vec<i32>>,
    /// The resized frame.
    resized: Vec<u8>,
}

impl Preprocessor {
    /// For a model taking `shape` from a camera rendering `frame_size` (width, height) frames,
    /// cropping `crop_top` and `crop_bottom` rows; `None` when they leave no row.
    pub fn new(
        shape: InputShape,
        frame_size: [usize; 2],
        crop_top: usize,
        crop_bottom: usize,
        colour: ColourSpace,
        scaling: PixelScaling,
    ) -> Option<Self> {
        let [frame_width, frame_height] = frame_size;
        let kept = frame_height
            .checked_sub(crop_top)?
            .checked_sub(crop_bottom)?;
        if kept == 0 || frame_width == 0 {
            return None;
        }
        let (rows, columns) = if kept == shape.height && frame_width == shape.width {
            (Vec::new(), Vec::new())
        } else {
            (blends(kept, shape.height), blends(frame_width, shape.width))
        };
        Some(Self {
            shape,
            frame_size,
            crop_top,
            colour,
            scaling,
            rows,
            columns,
            across: vec![Vec::new(); kept],
            resized: Vec::new(),
        })
    }

    /// The camera frame's width and height this preprocessor takes.
    pub fn frame_size(&self) -> [usize; 2] {
        self.frame_size
    }

    /// Writes the model's input for the camera's `frame` (the camera's size, and the model's
    /// channels: gray for 1, RGB for 3) into `out`.
    pub fn prepare(&mut self, frame: &Frame, out: &mut Vec<f32>) {
        let (h, w, c) = (self.shape.height, self.shape.width, self.shape.channels);
        debug_assert_eq!(
            [frame.width, frame.height, frame.channels],
            [self.frame_size[0], self.frame_size[1], c]
        );
        let pixels: &[u8] = if self.rows.is_empty() {
            &frame.data[self.crop_top * w * c..][..h * w * c]
        } else {
            self.resize(frame);
            &self.resized
        };
        out.clear();
        out.resize(h * w * c, 0.0);
        let scaling = self.scaling;
        if c == 1 {
            for (o, &p) in out.iter_mut().zip(pixels) {
                *o = scaling.apply(p);
            }
            return;
        }
        let plane = h * w;
        for (i, px) in pixels.chunks_exact(3).enumerate() {
            let rgb = [px[0], px[1], px[2]];
            let v = match self.colour {
                ColourSpace::Yuv => rgb_to_yuv(rgb),
                ColourSpace::Rgb => rgb,
            };
            for (k, &b) in v.iter().enumerate() {
                let at = match self.shape.layout {
                    Layout::Nhwc => 3 * i + k,
                    _ => k * plane + i,
                };
                out[at] = scaling.apply(b);
            }
        }
    }

    /// The cropped frame resized to the model's size into `self.resized`, as OpenCV's
    /// `INTER_LINEAR` resizes bytes on x86: each source row resized across into 2048ths, then
    /// rows blended in its fixed point (its SIMD path: rows in 128ths, products in 65536ths
    /// dropped, the sum rounded to quarters).
    fn resize(&mut self, frame: &Frame) {
        let c = self.shape.channels;
        let stride = frame.width * c;
        let cropped = &frame.data[self.crop_top * stride..];
        for across in &mut self.across {
            across.clear();
        }
        for blend in &self.rows {
            for r in [blend.first, blend.second] {
                if !self.across[r].is_empty() {
                    continue;
                }
                let row = &cropped[r * stride..(r + 1) * stride];
                let across = &mut self.across[r];
                for column in &self.columns {
                    let [a0, a1] = column.weights;
                    for k in 0..c {
                        let s0 = i32::from(row[column.first * c + k]);
                        let s1 = i32::from(row[column.second * c + k]);
                        across.push(s0 * a0 + s1 * a1);
                    }
                }
            }
        }
        self.resized.clear();
        for blend in &self.rows {
            let [wt, wb] = blend.weights;
            let (top, bottom) = (&self.across[blend.first], &self.across[blend.second]);
            self.resized.extend(top.iter().zip(bottom).map(|(&a, &b)| {
                (((((a >> 4) * wt) >> 16) + (((b >> 4) * wb) >> 16) + 2) >> 2).clamp(0, 255) as u8
            }));
        }
    }
}

/// Bilinear taps for resizing `from` pixels to `to` along one axis as OpenCV's `INTER_LINEAR`
/// does for bytes: pixel centres aligned (`x = (i + 0.5) · from / to − 0.5`, in f32), clamped at
/// the edges, each weight rounded to 2048ths.
fn blends(from: usize, to: usize) -> Vec<Blend> {
    let scale = 1.0 / (to as f64 / from as f64);
    let fixed = |w: f32| (w * 2048.0).round_ties_even() as i32;
    (0..to)
        .map(|r| {
            let y = ((r as f64 + 0.5) * scale - 0.5) as f32;
            let floor = y.floor();
            let mut frac = y - floor;
            let mut first = floor as i64;
            if first < 0 {
                first = 0;
                frac = 0.0;
            }
            let mut first = first as usize;
            if first >= from - 1 {
                first = from - 1;
                frac = 0.0;
            }
            Blend {
                first,
                second: (first + 1).min(from - 1),
                weights: [fixed(1.0 - frac), fixed(frac)],
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Deserialize)]
    struct Vectors {
        images: Vec<Image>,
    }

    #[derive(serde::Deserialize)]
    struct Image {
        pattern: String,
        samples: Vec<(usize, usize, [u8; 3])>,
    }

    /// The input images of `scripts/reference/dave2_contract_vectors.py`.
    fn pattern(name: &str) -> Frame {
        let (rows, cols) = (160, 320);
        let mut f = Frame::new(cols, rows, 3);
        for r in 0..rows {
            for c in 0..cols {
                for k in 0..3 {
                    let v = match name {
                        "stripes" => (r * 7 + c * 13 + k * 71 + (r * c) % 29) % 256,
                        "gradient" => (r + c / 2 + 60 * k) % 256,
                        "blocks" => ((r / 9 + c / 11) % 5) * 50 + k * 2,
                        _ => panic!("unknown pattern {name}"),
                    };
                    f.data[(r * cols + c) * 3 + k] = v as u8;
                }
            }
        }
        f
    }

    /// The competition's `preprocess` (crop rows 80 to the last but one, resize to 160 x 320,
    /// RGB to YUV) against its own answers.
    #[test]
    fn matches_the_competitions_preprocessing() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/reference/dave2_contract.json"
        );
        let vectors: Vectors =
            serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        let shape = InputShape {
            layout: Layout::Nhwc,
            channels: 3,
            height: 160,
            width: 320,
        };
        assert_eq!(vectors.images.len(), 3);
        for image in vectors.images {
            let mut p = Preprocessor::new(
                shape,
                [320, 160],
                80,
                1,
                ColourSpace::Yuv,
                PixelScaling::Raw,
            )
            .unwrap();
            let mut out = Vec::new();
            p.prepare(&pattern(&image.pattern), &mut out);
            for (r, c, want) in image.samples {
                let got: Vec<u8> = (0..3).map(|k| out[(r * 320 + c) * 3 + k] as u8).collect();
                assert_eq!(got, want, "{} at row {r}, column {c}", image.pattern);
            }
        }
    }

    #[derive(serde::Deserialize)]
    struct WholeImages {
        images: Vec<WholeImage>,
    }

    #[derive(serde::Deserialize)]
    struct WholeImage {
        pattern: String,
        /// Each row's YUV bytes in hex.
        rows: Vec<String>,
    }

    /// The Udacity course's `preprocess` (crop rows 60 to 135, resize to 200 x 66, RGB to YUV)
    /// against its own answers, every byte: the resize shrinks both ways here.
    #[test]
    fn matches_the_udacity_courses_preprocessing() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/reference/udacity_contract.json"
        );
        let vectors: WholeImages =
            serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        let shape = InputShape {
            layout: Layout::Nhwc,
            channels: 3,
            height: 66,
            width: 200,
        };
        assert_eq!(vectors.images.len(), 2);
        for image in vectors.images {
            let mut p = Preprocessor::new(
                shape,
                [320, 160],
                60,
                25,
                ColourSpace::Yuv,
                PixelScaling::Raw,
            )
            .unwrap();
            let mut out = Vec::new();
            p.prepare(&pattern(&image.pattern), &mut out);
            assert_eq!(image.rows.len(), 66);
            for (r, hex) in image.rows.iter().enumerate() {
                let want: Vec<u8> = (0..hex.len())
                    .step_by(2)
                    .map(|i| u8::from_str_radix(&hex[i..i + 2], 16).unwrap())
                    .collect();
                let got: Vec<u8> = out[r * 600..(r + 1) * 600]
                    .iter()
                    .map(|&v| v as u8)
                    .collect();
                assert_eq!(got, want, "{} row {r}", image.pattern);
            }
        }
    }

    #[test]
    fn layouts_scaling_and_gray() {
        let shape = InputShape {
            layout: Layout::Nchw,
            channels: 3,
            height: 8,
            width: 8,
        };
        let mut f = Frame::new(8, 8, 3);
        f.data
            .chunks_exact_mut(3)
            .for_each(|p| p.copy_from_slice(&[10, 20, 30]));
        let mut nchw = Vec::new();
        Preprocessor::new(shape, [8, 8], 0, 0, ColourSpace::Rgb, PixelScaling::Unit)
            .unwrap()
            .prepare(&f, &mut nchw);
        assert_eq!(
            (nchw[0], nchw[64], nchw[128]),
            (10.0 / 255.0, 20.0 / 255.0, 30.0 / 255.0)
        );
        let nhwc_shape = InputShape {
            layout: Layout::Nhwc,
            ..shape
        };
        let mut nhwc = Vec::new();
        Preprocessor::new(
            nhwc_shape,
            [8, 8],
            0,
            0,
            ColourSpace::Rgb,
            PixelScaling::Symmetric,
        )
        .unwrap()
        .prepare(&f, &mut nhwc);
        assert_eq!(
            &nhwc[..3],
            &[10.0 / 127.5 - 1.0, 20.0 / 127.5 - 1.0, 30.0 / 127.5 - 1.0]
        );
        let gray = InputShape {
            channels: 1,
            ..shape
        };
        let mut g = Frame::new(8, 8, 1);
        g.data = (0..64).collect();
        let mut out = Vec::new();
        Preprocessor::new(gray, [8, 8], 0, 0, ColourSpace::Yuv, PixelScaling::Raw)
            .unwrap()
            .prepare(&g, &mut out);
        assert_eq!(out, (0..64).map(|v| v as f32).collect::<Vec<_>>());
        assert!(
            Preprocessor::new(gray, [8, 8], 4, 4, ColourSpace::Yuv, PixelScaling::Raw).is_none()
        );
        assert!(
            Preprocessor::new(gray, [8, 8], 9, 0, ColourSpace::Yuv, PixelScaling::Raw).is_none()
        );
    }

    #[test]
    fn yuv_of_gray_is_gray_and_neutral() {
        for v in [0u8, 17, 128, 255] {
            assert_eq!(rgb_to_yuv([v, v, v]), [v, 128, 128]);
        }
    }
}
