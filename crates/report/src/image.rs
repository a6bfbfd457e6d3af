//! Rendered images as files: PNG (8-bit, for looking) and PFM (linear f32, for comparing).

use crate::error::{ReportError, Result};

/// An 8-bit RGBA image (row-major, top row first) as PNG bytes.
pub fn png_rgba(width: u32, height: u32, rgba: &[u8]) -> Result<Vec<u8>> {
    let path = format!("{width}×{height} image");
    png_8bit(png::ColorType::Rgba, (width, height), rgba, &path)
}

/// 8-bit pixels with `color`'s channels (row-major, top row first) as PNG bytes; errors name
/// `path`.
pub(crate) fn png_8bit(
    color: png::ColorType,
    (width, height): (u32, u32),
    pixels: &[u8],
    path: &str,
) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, width, height);
    enc.set_color(color);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header()
        .and_then(|mut w| w.write_image_data(pixels))
        .map_err(|e| ReportError::Plot {
            path: path.to_string(),
            message: e.to_string(),
        })?;
    Ok(out)
}

/// Portable float map (little-endian, bottom row first), the linear image for comparisons.
pub fn pfm(width: u32, height: u32, rgba: &[[f32; 4]]) -> Vec<u8> {
    let mut out = format!("PF\n{width} {height}\n-1.0\n").into_bytes();
    for y in (0..height as usize).rev() {
        for p in &rgba[y * width as usize..(y + 1) * width as usize] {
            for c in &p[..3] {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_decodes_to_the_pixels_given() {
        let rgba: Vec<u8> = (0..2 * 3 * 4).map(|i| (i * 10) as u8).collect();
        let bytes = png_rgba(2, 3, &rgba).unwrap();
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
            .read_info()
            .unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (2, 3));
        assert_eq!(&buf[..info.buffer_size()], &rgba[..]);
        assert!(png_rgba(2, 3, &rgba[..8]).is_err());
    }

    /// PFM: header, then RGB f32 little-endian with the bottom row first.
    #[test]
    fn pfm_stores_rows_bottom_first() {
        let img = [[1.0, 2.0, 3.0, 9.0], [4.0, 5.0, 6.0, 9.0]];
        let bytes = pfm(1, 2, &img);
        let header = b"PF\n1 2\n-1.0\n";
        assert_eq!(&bytes[..header.len()], header);
        let floats: Vec<f32> = bytes[header.len()..]
            .chunks(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        assert_eq!(floats, [4.0, 5.0, 6.0, 1.0, 2.0, 3.0]);
    }
}
