//! A minimal PNG writer: 8-bit RGB, one compressed IDAT.
//!
//! Enough for pictures of meshes: every viewer reads it. The chunks follow the PNG
//! specification (ISO/IEC 15948): signature, `IHDR`, `IDAT` holding a zlib stream (RFC 1950)
//! of the filtered scanlines (filter type 0 on every row) deflated by `miniz_oxide`
//! (RFC 1951), `IEND`; each chunk ends in the CRC-32 of its type and data. A mesh picture
//! of 800 × 800 takes about 120 KB (it took 1.9 MB stored uncompressed).

/// Deflate level (0–10 in `miniz_oxide`): 6, zlib's default, is within a few per cent of
/// the best size on mesh pictures at a fraction of the time of 9 or 10.
const DEFLATE_LEVEL: u8 = 6;

/// The PNG file of a `width × height` RGB image given row by row, top row first
/// (`rgb.len() = 3 · width · height`). `None` if the sizes disagree or are zero.
pub fn encode_rgb(width: u32, height: u32, rgb: &[u8]) -> Option<Vec<u8>> {
    let row = 3 * width as usize;
    if width == 0 || height == 0 || rgb.len() != row * height as usize {
        return None;
    }
    // Scanlines, each behind its filter byte (0: none)
    let mut raw = Vec::with_capacity((row + 1) * height as usize);
    for line in rgb.chunks_exact(row) {
        raw.push(0);
        raw.extend_from_slice(line);
    }
    // zlib: header, deflate blocks, Adler-32
    let z = miniz_oxide::deflate::compress_to_vec_zlib(&raw, DEFLATE_LEVEL);
    // The chunks
    let mut png = vec![0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];
    let mut ihdr = Vec::with_capacity(13);
    ihdr.extend_from_slice(&width.to_be_bytes());
    ihdr.extend_from_slice(&height.to_be_bytes());
    // Bit depth 8, colour type 2 (RGB), deflate, filter method 0, no interlace
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
    chunk(&mut png, b"IHDR", &ihdr);
    chunk(&mut png, b"IDAT", &z);
    chunk(&mut png, b"IEND", &[]);
    Some(png)
}

/// Appends a chunk: length, type, data, CRC-32 of type and data.
fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    out.extend_from_slice(&(data.len() as u32).to_be_bytes());
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let crc = crc32(kind.iter().chain(data));
    out.extend_from_slice(&crc.to_be_bytes());
}

/// CRC-32 (ISO 3309, reflected polynomial `0xEDB88320`), bit by bit.
fn crc32<'a>(bytes: impl Iterator<Item = &'a u8>) -> u32 {
    let mut c = 0xFFFF_FFFFu32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 == 1 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

#[cfg(test)]
pub mod check {
    //! A reader of the PNG files [`super::encode_rgb`] writes, for tests.

    /// `(width, height, rgb)` of a PNG written by [`super::encode_rgb`], with every CRC and
    /// the Adler-32 (by the inflater) checked.
    pub fn decode_rgb(png: &[u8]) -> Result<(u32, u32, Vec<u8>), String> {
        let sig = [0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];
        let mut rest = png.strip_prefix(&sig[..]).ok_or("no PNG signature")?;
        let (mut w, mut h, mut z) = (0, 0, Vec::new());
        while rest.len() >= 12 {
            let len = u32::from_be_bytes(rest[..4].try_into().unwrap()) as usize;
            let kind = &rest[4..8];
            let data = rest.get(8..8 + len).ok_or("chunk overruns the file")?;
            let crc = u32::from_be_bytes(rest[8 + len..12 + len].try_into().unwrap());
            if crc != super::crc32(kind.iter().chain(data)) {
                return Err(format!("bad CRC in {}", String::from_utf8_lossy(kind)));
            }
            match kind {
                b"IHDR" => {
                    w = u32::from_be_bytes(data[..4].try_into().unwrap());
                    h = u32::from_be_bytes(data[4..8].try_into().unwrap());
                    if data[8..] != [8, 2, 0, 0, 0] {
                        return Err("not 8-bit RGB".into());
                    }
                }
                b"IDAT" => z.extend_from_slice(data),
                b"IEND" => break,
                _ => return Err("unknown chunk".into()),
            }
            rest = &rest[12 + len..];
        }
        // The zlib stream, its Adler-32 checked by the inflater
        let raw = miniz_oxide::inflate::decompress_to_vec_zlib(&z)
            .map_err(|e| format!("bad zlib stream: {e:?}"))?;
        let row = 3 * w as usize + 1;
        let mut rgb = Vec::new();
        for line in raw.chunks_exact(row) {
            if line[0] != 0 {
                return Err("unexpected filter".into());
            }
            rgb.extend_from_slice(&line[1..]);
        }
        Ok((w, h, rgb))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_checksums() {
        // CRC-32 of "123456789" is 0xCBF43926.
        assert_eq!(crc32(b"123456789".iter()), 0xCBF4_3926);
    }

    #[test]
    fn round_trips_through_several_blocks() {
        let (w, h) = (300u32, 100u32);
        let rgb: Vec<u8> = (0..3 * w * h).map(|k| (k * 7 % 251) as u8).collect();
        let png = encode_rgb(w, h, &rgb).unwrap();
        assert_eq!(check::decode_rgb(&png).unwrap(), (w, h, rgb));
        // A flat picture compresses: 90,000 bytes of pixels in far less
        let flat = vec![200u8; 3 * 300 * 100];
        let png = encode_rgb(w, h, &flat).unwrap();
        assert!(png.len() < 2_000, "{} bytes", png.len());
        assert_eq!(check::decode_rgb(&png).unwrap(), (w, h, flat));
        assert!(encode_rgb(0, 1, &[]).is_none());
        assert!(encode_rgb(2, 2, &[0; 11]).is_none());
    }
}
