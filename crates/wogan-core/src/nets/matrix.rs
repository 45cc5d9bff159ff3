//! Row-major `f32` matrices, what the networks compute on, with the per-thread pool their
//! buffers come from and return to.

/// A row-major matrix. Its buffer comes from and returns to a per-thread pool (see
/// [`zeroed`]).
#[derive(Debug, PartialEq)]
pub(crate) struct Matrix {
    /// Number of rows.
    pub rows: usize,
    /// Number of columns.
    pub cols: usize,
    /// `rows × cols` values, row after row.
    pub data: Vec<f32>,
}

impl Matrix {
    /// A `[rows, cols]` matrix of row-major `data` (which must hold `rows × cols` values).
    pub fn new(data: Vec<f32>, rows: usize, cols: usize) -> Self {
        assert_eq!(data.len(), rows * cols, "a {rows}×{cols} matrix");
        Self { rows, cols, data }
    }

    /// Row `i`.
    #[cfg(test)]
    pub fn row(&self, i: usize) -> &[f32] {
        &self.data[i * self.cols..(i + 1) * self.cols]
    }

    /// A `[rows, cols]` matrix of zeros.
    pub fn zeros(rows: usize, cols: usize) -> Self {
        Self::new(zeroed(rows * cols), rows, cols)
    }

    /// Its values, leaving it empty.
    #[cfg(test)]
    pub fn take(mut self) -> Vec<f32> {
        std::mem::take(&mut self.data)
    }

    /// Rows `start..end` as a matrix of their own.
    pub fn row_range(&self, start: usize, end: usize) -> Matrix {
        let mut m = Matrix::zeros(end - start, self.cols);
        m.data
            .copy_from_slice(&self.data[start * self.cols..end * self.cols]);
        m
    }

    /// The transpose.
    pub fn transpose(&self) -> Matrix {
        transpose(&self.data, self.rows, self.cols)
    }
}

impl Clone for Matrix {
    fn clone(&self) -> Self {
        let mut m = Matrix::zeros(self.rows, self.cols);
        m.data.copy_from_slice(&self.data);
        m
    }
}

impl Drop for Matrix {
    fn drop(&mut self) {
        let data = std::mem::take(&mut self.data);
        if data.capacity() > 0 {
            // A thread being torn down has no pool left; the buffer is then simply freed.
            let _ = POOL.try_with(|pool| {
                let mut pool = pool.borrow_mut();
                if pool.len() < POOL_SIZE {
                    pool.push(data);
                }
            });
        }
    }
}

/// Buffers a thread keeps for reuse.
const POOL_SIZE: usize = 64;

thread_local! {
    /// Buffers of dropped matrices. A training step allocates and frees the same few dozen
    /// matrices every time; through the allocator that costs page faults (it returns the freed
    /// top of the heap to the system, and the next step touches it again).
    static POOL: std::cell::RefCell<Vec<Vec<f32>>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// `len` zeros, in a buffer from this thread's pool when one is large enough.
pub(crate) fn zeroed(len: usize) -> Vec<f32> {
    let reused = POOL
        .try_with(|pool| {
            let mut pool = pool.borrow_mut();
            // The smallest that fits, so that large buffers stay for large matrices.
            let (at, _) = pool
                .iter()
                .enumerate()
                .filter(|(_, b)| b.capacity() >= len)
                .min_by_key(|(_, b)| b.capacity())?;
            Some(pool.swap_remove(at))
        })
        .ok()
        .flatten();
    match reused {
        Some(mut b) => {
            b.clear();
            b.resize(len, 0.0);
            b
        }
        None => vec![0.0; len],
    }
}

/// The transpose of row-major `[rows, cols]` `data`.
fn transpose(data: &[f32], rows: usize, cols: usize) -> Matrix {
    // In blocks of 8 × 8 read row by row into registers and written column by column, so that
    // both sides move whole cache-line pieces; the ragged edges element by element.
    const B: usize = 8;
    let mut t = zeroed(rows * cols);
    let (full_rows, full_cols) = (rows - rows % B, cols - cols % B);
    for i0 in (0..full_rows).step_by(B) {
        for j0 in (0..full_cols).step_by(B) {
            let mut block = [[0.0f32; B]; B];
            for (r, block_row) in block.iter_mut().enumerate() {
                let start = (i0 + r) * cols + j0;
                block_row.copy_from_slice(&data[start..start + B]);
            }
            for c in 0..B {
                let start = (j0 + c) * rows + i0;
                let out: &mut [f32; B] = (&mut t[start..start + B]).try_into().expect("B");
                for (o, block_row) in out.iter_mut().zip(&block) {
                    *o = block_row[c];
                }
            }
        }
    }
    for i in 0..rows {
        let from = if i < full_rows { full_cols } else { 0 };
        for j in from..cols {
            t[j * rows + i] = data[i * cols + j];
        }
    }
    Matrix::new(t, cols, rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transposes_at_every_edge_of_the_blocks() {
        for (rows, cols) in [(13, 21), (16, 8), (1, 9), (9, 1), (0, 3), (128, 128)] {
            let m = Matrix::new((0..rows * cols).map(|v| v as f32).collect(), rows, cols);
            let t = m.transpose();
            assert_eq!((t.rows, t.cols), (cols, rows));
            for i in 0..rows {
                for j in 0..cols {
                    assert_eq!(t.data[j * rows + i], m.data[i * cols + j]);
                }
            }
            assert_eq!(t.transpose(), m);
        }
    }

    #[test]
    fn a_reused_buffer_comes_back_zeroed() {
        let mut m = Matrix::zeros(4, 4);
        m.data.iter_mut().for_each(|v| *v = 7.0);
        drop(m);
        assert!(Matrix::zeros(2, 3).data.iter().all(|v| *v == 0.0));
    }
}
