//! A fast plain-Rust forward pass of DAVE-2 (one frame, one core) on the weights of
//! [`Dave2Weights`]: each convolution is an im2col followed by a register-blocked matrix product
//! (4 output channels x 8 or 16 positions per block), with an AVX2+FMA version chosen at run time
//! where the CPU has it.

use super::camera::{FRAME_HEIGHT, FRAME_WIDTH};
use super::dave2_weights::{Dave2Weights, CONVS, DENSES, FRAME_PIXELS};

/// DAVE-2 ready for fast single-frame inference, with its scratch buffers.
#[derive(Debug, Clone)]
pub struct Dave2Net {
    weights: Dave2Weights,
    /// The convolutions' weights packed for [`gemm_relu`].
    packed: Vec<Vec<f32>>,
    /// The convolutions' im2col gathers.
    gathers: Vec<Gather>,
    /// Activations, ping-pong.
    a: Vec<f32>,
    b: Vec<f32>,
    /// im2col buffer.
    col: Vec<f32>,
    avx2: bool,
}

/// Output channels per block of the matrix product.
const OB: usize = 4;

impl Dave2Net {
    /// A network with `weights`.
    pub fn new(weights: &Dave2Weights) -> Self {
        #[cfg(target_arch = "x86_64")]
        let avx2 = std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma");
        #[cfg(not(target_arch = "x86_64"))]
        let avx2 = false;
        Self::with_simd(weights, avx2)
    }

    fn with_simd(weights: &Dave2Weights, avx2: bool) -> Self {
        let packed = CONVS
            .iter()
            .zip(&weights.convs)
            .map(|(&(ci, co, k, _), c)| pack(&c.weight, co, ci * k * k))
            .collect();
        let mut gathers = Vec::new();
        let (mut h, mut w) = (FRAME_HEIGHT, FRAME_WIDTH);
        for &(ci, _, k, s) in &CONVS {
            gathers.push(Gather::new(ci, h, w, k, s));
            (h, w) = ((h - k) / s + 1, (w - k) / s + 1);
        }
        Self {
            weights: weights.clone(),
            packed,
            gathers,
            a: Vec::new(),
            b: Vec::new(),
            col: Vec::new(),
            avx2,
        }
    }

    /// The weights.
    pub fn weights(&self) -> &Dave2Weights {
        &self.weights
    }

    /// The steering for one 66 x 200 grayscale frame (raw, unclamped network output).
    pub fn predict(&mut self, frame: &[u8]) -> f32 {
        assert_eq!(frame.len(), FRAME_PIXELS, "a 66 x 200 grayscale frame");
        let Self {
            weights,
            packed,
            gathers,
            a,
            b,
            col,
            avx2,
        } = self;
        a.clear();
        a.extend(frame.iter().map(|&p| f32::from(p) / 127.5 - 1.0));
        let (mut h, mut w) = (FRAME_HEIGHT, FRAME_WIDTH);
        for (((&(ci, co, k, s), cw), wp), g) in CONVS
            .iter()
            .zip(&weights.convs)
            .zip(packed.iter())
            .zip(gathers.iter())
        {
            let (oh, ow) = ((h - k) / s + 1, (w - k) / s + 1);
            let n = oh * ow;
            im2col(a, g, col);
            b.clear();
            b.resize(co * n, 0.0);
            gemm_relu(wp, &cw.bias, col, ci * k * k, n, b, *avx2);
            std::mem::swap(a, b);
            (h, w) = (oh, ow);
        }
        // Dense layers; `a` holds the flattened features in channel, row, column order.
        let last = DENSES.len() - 1;
        for (i, (&(di, dout), dw)) in DENSES.iter().zip(&weights.denses).enumerate() {
            debug_assert_eq!(a.len(), di);
            b.clear();
            b.extend_from_slice(&dw.bias);
            for (x, row) in a.iter().zip(dw.weight.chunks_exact(dout)) {
                for (y, wv) in b.iter_mut().zip(row) {
                    *y += x * wv;
                }
            }
            if i < last {
                for y in b.iter_mut() {
                    *y = y.max(0.0);
                }
            }
            std::mem::swap(a, b);
        }
        a[0]
    }
}

/// Output positions per panel of the im2col matrix.
const NB: usize = 16;

/// Where im2col reads: for row `r = (ic·k + ky)·k + kx` and position `j = oy·ow + ox` the input
/// index `rows[r] + positions[j]`; positions past the last (padding up to a whole panel) read
/// index `rows[r]` and are never stored.
#[derive(Debug, Clone)]
struct Gather {
    rows: Vec<usize>,
    positions: Vec<usize>,
}

impl Gather {
    fn new(ci: usize, h: usize, w: usize, k: usize, s: usize) -> Self {
        let (oh, ow) = ((h - k) / s + 1, (w - k) / s + 1);
        let mut rows = Vec::with_capacity(ci * k * k);
        for ic in 0..ci {
            for ky in 0..k {
                for kx in 0..k {
                    rows.push(ic * h * w + ky * w + kx);
                }
            }
        }
        let mut positions = Vec::with_capacity((oh * ow).div_ceil(NB) * NB);
        for oy in 0..oh {
            for ox in 0..ow {
                positions.push(oy * s * w + ox * s);
            }
        }
        positions.resize((oh * ow).div_ceil(NB) * NB, 0);
        Self { rows, positions }
    }
}

/// im2col in panels of [`NB`] output positions: `col[p·rows·NB + r·NB + i]` is row `r` at
/// position `p·NB + i` (see [`Gather`]).
fn im2col(input: &[f32], g: &Gather, col: &mut Vec<f32>) {
    let rows = g.rows.len();
    col.clear();
    col.resize(g.positions.len() * rows, 0.0);
    for (panel, pos) in col
        .chunks_exact_mut(rows * NB)
        .zip(g.positions.chunks_exact(NB))
    {
        for (dst, &r) in panel.chunks_exact_mut(NB).zip(&g.rows) {
            let src = &input[r..];
            for (d, &j) in dst.iter_mut().zip(pos) {
                *d = src[j];
            }
        }
    }
}

/// Packs a convolution's `[co][kk]` weights as `[co / OB][kk][OB]`.
fn pack(weight: &[f32], co: usize, kk: usize) -> Vec<f32> {
    let mut out = Vec::with_capacity(co * kk);
    for o0 in (0..co).step_by(OB) {
        for k in 0..kk {
            for r in 0..OB {
                out.push(weight[(o0 + r) * kk + k]);
            }
        }
    }
    out
}

/// `out[o][j] = relu(bias[o] + Σ_k weight[o][k]·col[k][j])`, `o < co`, `k < kk`, `j < n`, with
/// `wpack` from [`pack`] and `col` from [`im2col`].
#[allow(clippy::too_many_arguments)]
fn gemm_relu(
    wpack: &[f32],
    bias: &[f32],
    col: &[f32],
    kk: usize,
    n: usize,
    out: &mut [f32],
    avx2: bool,
) {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: the CPU has AVX2 and FMA (checked in `Dave2Net::new`).
        unsafe { gemm_avx2(wpack, bias, col, kk, n, out) };
        return;
    }
    let _ = avx2;
    gemm_panels::<false>(wpack, bias, col, kk, n, out);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn gemm_avx2(
    wpack: &[f32],
    bias: &[f32],
    col: &[f32],
    kk: usize,
    n: usize,
    out: &mut [f32],
) {
    gemm_panels::<true>(wpack, bias, col, kk, n, out);
}

#[inline(always)]
fn gemm_panels<const FMA: bool>(
    wpack: &[f32],
    bias: &[f32],
    col: &[f32],
    kk: usize,
    n: usize,
    out: &mut [f32],
) {
    for (p, panel) in col.chunks_exact(kk * NB).enumerate() {
        let j0 = p * NB;
        let len = NB.min(n - j0);
        for (blk, wb) in wpack.chunks_exact(kk * OB).enumerate() {
            let o0 = blk * OB;
            let mut acc = [[0.0f32; NB]; OB];
            for (r, a) in acc.iter_mut().enumerate() {
                *a = [bias[o0 + r]; NB];
            }
            if FMA {
                let mut v = acc;
                for (c, w) in panel.chunks_exact(NB).zip(wb.chunks_exact(OB)) {
                    let c: &[f32; NB] = c.try_into().expect("a panel row");
                    let w: &[f32; OB] = w.try_into().expect("a weight group");
                    for r in 0..OB {
                        for j in 0..NB {
                            v[r][j] = w[r].mul_add(c[j], v[r][j]);
                        }
                    }
                }
                acc = v;
            } else {
                // Without AVX (16 SSE registers): one output channel at a time.
                for (r, a) in acc.iter_mut().enumerate() {
                    let mut v = *a;
                    for (c, w) in panel.chunks_exact(NB).zip(wb.chunks_exact(OB)) {
                        let c: &[f32; NB] = c.try_into().expect("a panel row");
                        let wv = w[r];
                        for j in 0..NB {
                            v[j] += wv * c[j];
                        }
                    }
                    *a = v;
                }
            }
            for (r, a) in acc.iter().enumerate() {
                let dst = &mut out[(o0 + r) * n + j0..(o0 + r) * n + j0 + len];
                for (d, v) in dst.iter_mut().zip(a) {
                    *d = v.max(0.0);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::road::Road;
    use crate::vision::{Camera, RoadScene};

    /// Three camera frames along a bend.
    pub(crate) fn frames() -> Vec<u8> {
        let pts = [[100.0, 10.0], [100.0, 40.0], [120.0, 70.0], [150.0, 80.0]];
        let road = Road::new(&pts).unwrap();
        let scene = RoadScene::new(&road);
        let cam = Camera::default();
        let mut out = Vec::new();
        for (i, h) in [1.5, 1.7, 1.3].into_iter().enumerate() {
            out.extend(
                cam.render(&scene, [101.0 + i as f64, 20.0 + 5.0 * i as f64], h)
                    .data,
            );
        }
        out
    }

    /// The AVX2 path against the scalar one (the burn model is the reference for both; the
    /// `driver-training` crate checks the default path against it).
    #[test]
    fn the_simd_path_matches_the_scalar_path() {
        let frames = frames();
        for seed in [1, 2] {
            let w = Dave2Weights::from_seed(seed);
            let mut scalar = Dave2Net::with_simd(&w, false);
            let mut simd = Dave2Net::with_simd(&w, Dave2Net::new(&w).avx2);
            for f in frames.chunks_exact(FRAME_PIXELS) {
                let (a, b) = (scalar.predict(f), simd.predict(f));
                assert!((a - b).abs() < 1e-4, "seed {seed}: {a} vs {b}");
            }
        }
    }
}
