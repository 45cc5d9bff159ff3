//! A camera frame: pixels in rows, gray or RGB, and writing it as PNG.

/// An image, row-major from the top-left, `channels` bytes per pixel (1: gray, 3: RGB).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Frame {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// 1 (grayscale) or 3 (RGB).
    pub channels: usize,
    /// The pixel values.
    pub data: Vec<u8>,
}

impl Frame {
    /// A black frame.
    pub fn new(width: usize, height: usize, channels: usize) -> Self {
        Self {
            width,
            height,
            channels,
            data: vec![0; width * height * channels],
        }
    }

    /// The value of channel `c` at row `r`, column `col`.
    pub fn get(&self, r: usize, col: usize, c: usize) -> u8 {
        self.data[(r * self.width + col) * self.channels + c]
    }
}

/// Writes `frame` as an 8-bit grayscale or RGB PNG.
pub fn write_png(path: &std::path::Path, frame: &Frame) -> std::io::Result<()> {
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut encoder = png::Encoder::new(file, frame.width as u32, frame.height as u32);
    encoder.set_color(match frame.channels {
        1 => png::ColorType::Grayscale,
        3 => png::ColorType::Rgb,
        n => {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!("a frame of {n} channels"),
            ))
        }
    });
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
    writer
        .write_image_data(&frame.data)
        .map_err(std::io::Error::other)?;
    writer.finish().map_err(std::io::Error::other)
}
