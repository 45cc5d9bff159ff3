//! The matrix products WOGAN's networks are made of.
//!
//! The networks are tiny (at most 128 wide, batches of 32 to 512 rows), so what costs besides the
//! arithmetic is everything around it: allocating, dispatching, walking memory twice. Each
//! product here is one pass that keeps a tile of the result in registers and writes it once,
//! with the layer's bias and activation applied as it is written ([`Epilogue`]).
//!
//! Two kernels cover every shape the networks need:
//! - *wide* (`n >= 8` result columns): each result row is built as a sum of rows of `b` scaled by
//!   the row's entries of `a`, vectorised along the columns, in tiles of 4 rows × 64 columns
//!   (AVX-512, 32 registers) or 2 rows × 32 columns (16 registers); `a` may be read transposed,
//!   so `aᵀ·b` (weight gradients) needs no copy;
//! - *narrow* (`n < 8`, e.g. a single critic value or the gradient with respect to a 5-dimensional
//!   input): each result is a dot product of two contiguous rows, vectorised along them.
//!
//! Each result element sums its products in the order of `k` in the wide kernel and in eight
//! interleaved partial sums in the narrow one, whatever the tiling or the vector width: the same
//! inputs always give the same bits on one machine, which the runs' determinism rests on. The
//! kernels are compiled for AVX-512 or AVX2 with FMA where the CPU has them (checked at run
//! time), and as portable code without fused multiply-adds elsewhere.

use super::matrix::{zeroed, Matrix};

/// A layer's activation, applied as its output is written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Activation {
    /// None: the pre-activation itself.
    Identity,
    /// `max(x, 0)`.
    Relu,
    /// `x` where positive, `slope · x` elsewhere.
    LeakyRelu(f32),
}

impl Activation {
    #[inline(always)]
    fn apply(self, x: f32) -> f32 {
        match self {
            Activation::Identity => x,
            Activation::Relu => {
                if x > 0.0 {
                    x
                } else {
                    0.0
                }
            }
            Activation::LeakyRelu(slope) => {
                if x > 0.0 {
                    x
                } else {
                    x * slope
                }
            }
        }
    }
}

/// What a product does with each result element as it writes it.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Epilogue<'a> {
    /// Writes the product.
    Plain,
    /// Writes `activation(product + bias[column])`: a dense layer in one pass.
    Layer(&'a [f32], Activation),
}

impl Epilogue<'_> {
    #[inline(always)]
    fn apply(self, j: usize, x: f32) -> f32 {
        match self {
            Epilogue::Plain => x,
            Epilogue::Layer(bias, act) => act.apply(x + bias[j]),
        }
    }
}

/// `a · b`, with `a: [m, k]` and `b: [k, n]`.
pub(crate) fn matmul(a: &Matrix, b: &Matrix, epilogue: Epilogue) -> Matrix {
    assert_eq!(a.cols, b.rows, "inner dimensions");
    if b.cols < WIDE {
        return narrow(
            &a.data,
            a.rows,
            a.cols,
            &b.transpose().data,
            b.cols,
            epilogue,
        );
    }
    let lhs = Lhs {
        data: &a.data,
        row_stride: a.cols,
        col_stride: 1,
    };
    wide(lhs, a.rows, a.cols, &b.data, b.cols, epilogue)
}

/// `a · bᵀ`, with `a: [m, k]` and `b: [n, k]`.
pub(crate) fn matmul_bt(a: &Matrix, b: &Matrix) -> Matrix {
    assert_eq!(a.cols, b.cols, "inner dimensions");
    if b.rows < WIDE {
        return narrow(&a.data, a.rows, a.cols, &b.data, b.rows, Epilogue::Plain);
    }
    matmul(a, &b.transpose(), Epilogue::Plain)
}

/// `aᵀ · b`, with `a: [k, m]` and `b: [k, n]` (a weight gradient: inputs by output gradients).
pub(crate) fn matmul_at(a: &Matrix, b: &Matrix) -> Matrix {
    assert_eq!(a.rows, b.rows, "inner dimensions");
    if b.cols < WIDE {
        // (bᵀ a)ᵀ: wide along a's columns instead.
        let bt = Lhs {
            data: &b.data,
            row_stride: 1,
            col_stride: b.cols,
        };
        let r = wide(bt, b.cols, b.rows, &a.data, a.cols, Epilogue::Plain);
        return r.transpose();
    }
    let at = Lhs {
        data: &a.data,
        row_stride: 1,
        col_stride: a.cols,
    };
    wide(at, a.cols, a.rows, &b.data, b.cols, Epilogue::Plain)
}

/// Result columns from which the wide kernel is used.
const WIDE: usize = 8;

/// The left operand of the wide kernel: element `(i, p)` at `data[i·row_stride + p·col_stride]`.
#[derive(Clone, Copy)]
struct Lhs<'a> {
    data: &'a [f32],
    row_stride: usize,
    col_stride: usize,
}

/// `lhs · b` for `lhs: [m, k]`, `b: [k, n]` row-major, by the fastest kernel this CPU runs.
fn wide(lhs: Lhs, m: usize, k: usize, b: &[f32], n: usize, epilogue: Epilogue) -> Matrix {
    wide_on(simd(), lhs, m, k, b, n, epilogue)
}

/// As [`wide`], on the kernel for `path`, which this CPU must run.
fn wide_on(
    path: Simd,
    lhs: Lhs,
    m: usize,
    k: usize,
    b: &[f32],
    n: usize,
    epilogue: Epilogue,
) -> Matrix {
    assert!(path <= simd(), "{path:?} kernels on a CPU without them");
    assert!(
        m == 0 || k == 0 || (m - 1) * lhs.row_stride + (k - 1) * lhs.col_stride < lhs.data.len()
    );
    assert_eq!(b.len(), k * n);
    let mut c = zeroed(m * n);
    match path {
        // SAFETY (both): the function is compiled for CPU features this CPU has (asserted
        // above); it is otherwise safe code.
        #[cfg(target_arch = "x86_64")]
        Simd::Avx512 => unsafe { wide_avx512(lhs, m, k, b, n, epilogue, &mut c) },
        #[cfg(target_arch = "x86_64")]
        Simd::Avx2 => unsafe { wide_avx2(lhs, m, k, b, n, epilogue, &mut c) },
        _ => wide_kernel::<false>(lhs, m, 0, k, b, n, epilogue, &mut c),
    }
    Matrix::new(c, m, n)
}

/// `a · bᵀ` for `a: [m, k]`, `bt: [n, k]` row-major, by the fastest kernel this CPU runs.
fn narrow(a: &[f32], m: usize, k: usize, bt: &[f32], n: usize, epilogue: Epilogue) -> Matrix {
    narrow_on(simd(), a, m, k, bt, n, epilogue)
}

/// As [`narrow`], on the kernel for `path`, which this CPU must run.
fn narrow_on(
    path: Simd,
    a: &[f32],
    m: usize,
    k: usize,
    bt: &[f32],
    n: usize,
    epilogue: Epilogue,
) -> Matrix {
    assert!(path <= simd(), "{path:?} kernels on a CPU without them");
    assert_eq!(a.len(), m * k);
    assert_eq!(bt.len(), n * k);
    let mut c = zeroed(m * n);
    match path {
        // SAFETY: as in `wide_on`.
        #[cfg(target_arch = "x86_64")]
        Simd::Avx512 | Simd::Avx2 => unsafe { narrow_avx2(a, k, bt, n, epilogue, &mut c) },
        _ => narrow_kernel::<false>(a, k, bt, n, epilogue, &mut c),
    }
    Matrix::new(c, m, n)
}

/// The vector instructions a kernel is compiled for, in increasing order.
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
enum Simd {
    /// Neither of the others: the portable kernel, without fused multiply-adds.
    None,
    /// AVX2 (16 registers of 8 lanes) with FMA.
    Avx2,
    /// AVX-512 (32 registers of 16 lanes) with FMA.
    Avx512,
}

/// The best this CPU runs. Every path with FMA sums each result in the same order, so AVX-512 and
/// AVX2 give the same bits.
fn simd() -> Simd {
    #[cfg(target_arch = "x86_64")]
    {
        use std::is_x86_feature_detected as has;
        if has!("avx512f") && has!("avx512vl") && has!("avx2") && has!("fma") {
            return Simd::Avx512;
        } else if has!("avx2") && has!("fma") {
            return Simd::Avx2;
        }
    }
    Simd::None
}

/// Tiles of 4 rows × 64 columns, 8 × 32 and 8 × 16 in AVX-512 registers, then the AVX2
/// kernel for what is left.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,avx512f,avx512vl")]
fn wide_avx512(lhs: Lhs, m: usize, k: usize, b: &[f32], n: usize, ep: Epilogue, c: &mut [f32]) {
    let mut j = 0;
    while j + 64 <= n {
        for_rows::<4>(m, |i, rows| match rows {
            4 => avx512_tile::<4, 4, 64>(lhs, i, j, k, b, n, ep, c),
            _ => avx512_tile::<1, 4, 64>(lhs, i, j, k, b, n, ep, c),
        });
        j += 64;
    }
    while j + 32 <= n {
        for_rows::<8>(m, |i, rows| match rows {
            8 => avx512_tile::<8, 2, 32>(lhs, i, j, k, b, n, ep, c),
            _ => avx512_tile::<1, 2, 32>(lhs, i, j, k, b, n, ep, c),
        });
        j += 32;
    }
    while j + 16 <= n {
        for_rows::<8>(m, |i, rows| match rows {
            8 => avx512_tile::<8, 1, 16>(lhs, i, j, k, b, n, ep, c),
            _ => avx512_tile::<1, 1, 16>(lhs, i, j, k, b, n, ep, c),
        });
        j += 16;
    }
    wide_avx2_from(lhs, m, j, k, b, n, ep, c);
}

/// Calls `tile(i, R)` for rows `i..i+R` while `R` rows are left, then `tile(i, 1)` for each
/// remaining row.
#[inline(always)]
fn for_rows<const R: usize>(m: usize, mut tile: impl FnMut(usize, usize)) {
    let mut i = 0;
    while i + R <= m {
        tile(i, R);
        i += R;
    }
    while i < m {
        tile(i, 1);
        i += 1;
    }
}

/// Result rows `i..i+R`, columns `j..j+W` (`W = 16·V`), summed over `k` in `R × V` AVX-512
/// registers and written once through the epilogue. (The compiler keeps arrays of vector
/// registers in registers where it spills a float array this large.)
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
#[allow(clippy::too_many_arguments)]
fn avx512_tile<const R: usize, const V: usize, const W: usize>(
    lhs: Lhs,
    i: usize,
    j: usize,
    k: usize,
    b: &[f32],
    n: usize,
    ep: Epilogue,
    c: &mut [f32],
) {
    use std::arch::x86_64::{
        _mm512_fmadd_ps, _mm512_loadu_ps, _mm512_set1_ps, _mm512_setzero_ps, _mm512_storeu_ps,
    };
    assert_eq!(W, 16 * V);
    let mut acc = [[_mm512_setzero_ps(); V]; R];
    for p in 0..k {
        let b_row = &b[p * n + j..p * n + j + W];
        let mut bv = [_mm512_setzero_ps(); V];
        for (v, chunk) in bv.iter_mut().zip(b_row.chunks_exact(16)) {
            // SAFETY: `chunk` holds the 16 floats an unaligned 512-bit load reads.
            *v = unsafe { _mm512_loadu_ps(chunk.as_ptr()) };
        }
        for (r, acc_r) in acc.iter_mut().enumerate() {
            let x = _mm512_set1_ps(lhs.data[(i + r) * lhs.row_stride + p * lhs.col_stride]);
            for (a, y) in acc_r.iter_mut().zip(&bv) {
                *a = _mm512_fmadd_ps(x, *y, *a);
            }
        }
    }
    for (r, acc_r) in acc.iter().enumerate() {
        let mut row = [0.0f32; W];
        for (a, chunk) in acc_r.iter().zip(row.chunks_exact_mut(16)) {
            // SAFETY: `chunk` has room for the 16 floats an unaligned 512-bit store writes.
            unsafe { _mm512_storeu_ps(chunk.as_mut_ptr(), *a) };
        }
        let out: &mut [f32; W] = (&mut c[(i + r) * n + j..(i + r) * n + j + W])
            .try_into()
            .expect("W columns");
        store(out, &row, j, ep);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn wide_avx2(lhs: Lhs, m: usize, k: usize, b: &[f32], n: usize, ep: Epilogue, c: &mut [f32]) {
    wide_avx2_from(lhs, m, 0, k, b, n, ep, c);
}

/// Result columns from `j` on: tiles of 2 rows × 32 columns and 4 × 8 in AVX2 registers, then
/// the portable kernel (with FMA) for the last columns.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[allow(clippy::too_many_arguments)]
fn wide_avx2_from(
    lhs: Lhs,
    m: usize,
    mut j: usize,
    k: usize,
    b: &[f32],
    n: usize,
    ep: Epilogue,
    c: &mut [f32],
) {
    while j + 32 <= n {
        for_rows::<2>(m, |i, rows| match rows {
            2 => avx2_tile::<2, 4, 32>(lhs, i, j, k, b, n, ep, c),
            _ => avx2_tile::<1, 4, 32>(lhs, i, j, k, b, n, ep, c),
        });
        j += 32;
    }
    while j + 8 <= n {
        for_rows::<4>(m, |i, rows| match rows {
            4 => avx2_tile::<4, 1, 8>(lhs, i, j, k, b, n, ep, c),
            _ => avx2_tile::<1, 1, 8>(lhs, i, j, k, b, n, ep, c),
        });
        j += 8;
    }
    wide_kernel::<true>(lhs, m, j, k, b, n, ep, c);
}

/// As [`avx512_tile`], in `R × V` AVX2 registers of 8 lanes (`W = 8·V`).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
#[allow(clippy::too_many_arguments)]
fn avx2_tile<const R: usize, const V: usize, const W: usize>(
    lhs: Lhs,
    i: usize,
    j: usize,
    k: usize,
    b: &[f32],
    n: usize,
    ep: Epilogue,
    c: &mut [f32],
) {
    use std::arch::x86_64::{
        _mm256_fmadd_ps, _mm256_loadu_ps, _mm256_set1_ps, _mm256_setzero_ps, _mm256_storeu_ps,
    };
    assert_eq!(W, 8 * V);
    let mut acc = [[_mm256_setzero_ps(); V]; R];
    for p in 0..k {
        let b_row = &b[p * n + j..p * n + j + W];
        let mut bv = [_mm256_setzero_ps(); V];
        for (v, chunk) in bv.iter_mut().zip(b_row.chunks_exact(8)) {
            // SAFETY: `chunk` holds the 8 floats an unaligned 256-bit load reads.
            *v = unsafe { _mm256_loadu_ps(chunk.as_ptr()) };
        }
        for (r, acc_r) in acc.iter_mut().enumerate() {
            let x = _mm256_set1_ps(lhs.data[(i + r) * lhs.row_stride + p * lhs.col_stride]);
            for (a, y) in acc_r.iter_mut().zip(&bv) {
                *a = _mm256_fmadd_ps(x, *y, *a);
            }
        }
    }
    for (r, acc_r) in acc.iter().enumerate() {
        let mut row = [0.0f32; W];
        for (a, chunk) in acc_r.iter().zip(row.chunks_exact_mut(8)) {
            // SAFETY: `chunk` has room for the 8 floats an unaligned 256-bit store writes.
            unsafe { _mm256_storeu_ps(chunk.as_mut_ptr(), *a) };
        }
        let out: &mut [f32; W] = (&mut c[(i + r) * n + j..(i + r) * n + j + W])
            .try_into()
            .expect("W columns");
        store(out, &row, j, ep);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn narrow_avx2(a: &[f32], k: usize, bt: &[f32], n: usize, ep: Epilogue, c: &mut [f32]) {
    narrow_kernel::<true>(a, k, bt, n, ep, c);
}

/// `acc + x·y`, fused where the kernel is compiled for FMA.
#[inline(always)]
fn mul_add<const FMA: bool>(x: f32, y: f32, acc: f32) -> f32 {
    if FMA {
        x.mul_add(y, acc)
    } else {
        acc + x * y
    }
}

/// The portable wide kernel, from result column `j` on: tiles of 2 rows × 32 columns, 4 × 8,
/// then single columns (the compiler vectorises the tile rows).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn wide_kernel<const FMA: bool>(
    lhs: Lhs,
    m: usize,
    mut j: usize,
    k: usize,
    b: &[f32],
    n: usize,
    ep: Epilogue,
    c: &mut [f32],
) {
    // Column blocks outside, rows inside: a block of `b` stays in L1 for all rows.
    while j + 32 <= n {
        wide_columns::<FMA, 2, 32>(lhs, m, j, k, b, n, ep, c);
        j += 32;
    }
    while j + 8 <= n {
        wide_columns::<FMA, 4, 8>(lhs, m, j, k, b, n, ep, c);
        j += 8;
    }
    while j < n {
        wide_columns::<FMA, 4, 1>(lhs, m, j, k, b, n, ep, c);
        j += 1;
    }
}

/// Result columns `j..j+W`, `R` rows at a time.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn wide_columns<const FMA: bool, const R: usize, const W: usize>(
    lhs: Lhs,
    m: usize,
    j: usize,
    k: usize,
    b: &[f32],
    n: usize,
    ep: Epilogue,
    c: &mut [f32],
) {
    let mut i = 0;
    while i + R <= m {
        wide_tile::<FMA, R, W>(lhs, i, j, k, b, n, ep, c);
        i += R;
    }
    while i < m {
        wide_tile::<FMA, 1, W>(lhs, i, j, k, b, n, ep, c);
        i += 1;
    }
}

/// Result rows `i..i+R`, columns `j..j+W`, summed over `k` in registers and written once.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn wide_tile<const FMA: bool, const R: usize, const W: usize>(
    lhs: Lhs,
    i: usize,
    j: usize,
    k: usize,
    b: &[f32],
    n: usize,
    ep: Epilogue,
    c: &mut [f32],
) {
    let mut acc = [[0.0f32; W]; R];
    for p in 0..k {
        let b_row: &[f32; W] = b[p * n + j..p * n + j + W].try_into().expect("W columns");
        for (r, acc_r) in acc.iter_mut().enumerate() {
            let x = lhs.data[(i + r) * lhs.row_stride + p * lhs.col_stride];
            for (a, y) in acc_r.iter_mut().zip(b_row) {
                *a = mul_add::<FMA>(x, *y, *a);
            }
        }
    }
    for (r, acc_r) in acc.iter().enumerate() {
        let out: &mut [f32; W] = (&mut c[(i + r) * n + j..(i + r) * n + j + W])
            .try_into()
            .expect("W columns");
        store(out, acc_r, j, ep);
    }
}

/// Writes a tile row `acc` (result columns `j..j+W`) through the epilogue; one loop per case,
/// so that each vectorises.
#[inline(always)]
fn store<const W: usize>(out: &mut [f32; W], acc: &[f32; W], j: usize, ep: Epilogue) {
    match ep {
        Epilogue::Plain => *out = *acc,
        Epilogue::Layer(bias, act) => {
            let bias: &[f32; W] = bias[j..j + W].try_into().expect("W columns");
            let biased = out.iter_mut().zip(acc).zip(bias);
            match act {
                Activation::Identity => biased.for_each(|((o, a), b)| *o = a + b),
                Activation::Relu => biased.for_each(|((o, a), b)| {
                    let x = a + b;
                    *o = if x > 0.0 { x } else { 0.0 };
                }),
                Activation::LeakyRelu(slope) => biased.for_each(|((o, a), b)| {
                    let x = a + b;
                    *o = if x > 0.0 { x } else { x * slope };
                }),
            }
        }
    }
}

/// Lanes of the narrow kernel's partial sums.
const LANES: usize = 8;

#[inline(always)]
fn narrow_kernel<const FMA: bool>(
    a: &[f32],
    k: usize,
    bt: &[f32],
    n: usize,
    ep: Epilogue,
    c: &mut [f32],
) {
    if n == 0 {
        return;
    }
    if k == 0 {
        for (idx, o) in c.iter_mut().enumerate() {
            *o = ep.apply(idx % n.max(1), 0.0);
        }
        return;
    }
    for (a_row, c_row) in a.chunks_exact(k).zip(c.chunks_exact_mut(n)) {
        for (jj, (b_row, o)) in bt.chunks_exact(k).zip(c_row.iter_mut()).enumerate() {
            let mut acc = [0.0f32; LANES];
            let mut a_chunks = a_row.chunks_exact(LANES);
            let mut b_chunks = b_row.chunks_exact(LANES);
            for (x, y) in (&mut a_chunks).zip(&mut b_chunks) {
                for l in 0..LANES {
                    acc[l] = mul_add::<FMA>(x[l], y[l], acc[l]);
                }
            }
            for (l, (x, y)) in a_chunks
                .remainder()
                .iter()
                .zip(b_chunks.remainder())
                .enumerate()
            {
                acc[l] = mul_add::<FMA>(*x, *y, acc[l]);
            }
            let sum =
                ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7]));
            *o = ep.apply(jj, sum);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn naive(a: &Matrix, b: &Matrix) -> Vec<f64> {
        let mut c = vec![0.0; a.rows * b.cols];
        for i in 0..a.rows {
            for j in 0..b.cols {
                for p in 0..a.cols {
                    c[i * b.cols + j] +=
                        f64::from(a.data[i * a.cols + p]) * f64::from(b.data[p * b.cols + j]);
                }
            }
        }
        c
    }

    fn filled(rows: usize, cols: usize, seed: u32) -> Matrix {
        let data = (0..rows * cols)
            .map(|i| {
                ((i as u32).wrapping_mul(2654435761).wrapping_add(seed) % 1000) as f32 / 500.0 - 1.0
            })
            .collect();
        Matrix::new(data, rows, cols)
    }

    fn assert_near(actual: &Matrix, expected: &[f64]) {
        assert_eq!(actual.data.len(), expected.len());
        for (a, e) in actual.data.iter().zip(expected) {
            assert!(
                (f64::from(*a) - e).abs() < 1e-4 * (1.0 + e.abs()),
                "{a} vs {e}"
            );
        }
    }

    #[test]
    fn products_match_a_naive_sum_at_every_shape_the_networks_use() {
        // Odd sizes reach every tile width and the single-row remainder.
        for (m, k, n) in [
            (97, 5, 128),
            (96, 128, 128),
            (33, 128, 1),
            (7, 128, 5),
            (300, 32, 32),
            (3, 10, 41),
            (0, 4, 9),
            (2, 0, 9),
        ] {
            let a = filled(m, k, 1);
            let b = filled(k, n, 2);
            assert_near(&matmul(&a, &b, Epilogue::Plain), &naive(&a, &b));
            assert_near(&matmul_bt(&a, &b.transpose()), &naive(&a, &b));
            assert_near(&matmul_at(&a.transpose(), &b), &naive(&a, &b));
        }
    }

    #[test]
    fn every_kernel_this_cpu_runs_gives_the_products_and_the_fma_ones_the_same_bits() {
        for (m, k, n) in [(9, 128, 128), (13, 5, 96), (11, 32, 40), (5, 7, 3)] {
            let a = filled(m, k, 3);
            let b = filled(k, n, 4);
            let bt = b.transpose();
            let expected = naive(&a, &b);
            let lhs = Lhs {
                data: &a.data,
                row_stride: k,
                col_stride: 1,
            };
            let mut fma: Option<(Vec<f32>, Vec<f32>)> = None;
            for path in [Simd::None, Simd::Avx2, Simd::Avx512] {
                if path > simd() {
                    continue;
                }
                let wide = wide_on(path, lhs, m, k, &b.data, n, Epilogue::Plain);
                let narrow = narrow_on(path, &a.data, m, k, &bt.data, n, Epilogue::Plain);
                assert_near(&wide, &expected);
                assert_near(&narrow, &expected);
                if path == Simd::None {
                    continue;
                }
                match &fma {
                    Some((w, n)) => assert!(w == &wide.data && n == &narrow.data, "{path:?}"),
                    None => fma = Some((wide.data.clone(), narrow.data.clone())),
                }
            }
        }
    }

    #[test]
    fn the_epilogue_adds_the_bias_and_activates() {
        let a = Matrix::new(vec![1.0, -2.0], 2, 1);
        for n in [1, 9] {
            let b = Matrix::new(vec![1.0; n], 1, n);
            let bias = vec![0.5; n];
            let out = matmul(&a, &b, Epilogue::Layer(&bias, Activation::LeakyRelu(0.1)));
            assert_eq!(out.row(0), vec![1.5; n].as_slice());
            assert_eq!(out.row(1), vec![-0.15; n].as_slice());
            let out = matmul(&a, &b, Epilogue::Layer(&bias, Activation::Relu));
            assert_eq!(out.row(1), vec![0.0; n].as_slice());
        }
    }
}
