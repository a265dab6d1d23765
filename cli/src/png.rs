//! A minimal PNG writer: 8-bit RGB, one IDAT of stored (uncompressed) deflate blocks.
//!
//! Enough for pictures of meshes: every viewer reads it, and it needs no dependency. The
//! chunks follow the PNG specification (ISO/IEC 15948): signature, `IHDR`, `IDAT` holding a
//! zlib stream (RFC 1950) of stored deflate blocks (RFC 1951, `BTYPE = 00`) of the
//! filtered scanlines (filter type 0 on every row), `IEND`; each chunk ends in the CRC-32
//! of its type and data.

/// Largest payload of one stored deflate block.
const STORED_BLOCK: usize = 65_535;

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
    // zlib: header (deflate, 32K window, no dictionary, check bits), stored blocks, Adler-32
    let mut z = Vec::with_capacity(raw.len() + raw.len() / STORED_BLOCK * 5 + 16);
    z.extend_from_slice(&[0x78, 0x01]);
    let blocks: Vec<&[u8]> = raw.chunks(STORED_BLOCK).collect();
    for (k, block) in blocks.iter().enumerate() {
        z.push(u8::from(k + 1 == blocks.len()));
        let len = block.len() as u16;
        z.extend_from_slice(&len.to_le_bytes());
        z.extend_from_slice(&(!len).to_le_bytes());
        z.extend_from_slice(block);
    }
    z.extend_from_slice(&adler32(&raw).to_be_bytes());
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

/// Adler-32 (RFC 1950).
fn adler32(bytes: &[u8]) -> u32 {
    let (mut a, mut b) = (1u32, 0u32);
    for chunk in bytes.chunks(5552) {
        for &x in chunk {
            a += u32::from(x);
            b += a;
        }
        a %= 65_521;
        b %= 65_521;
    }
    (b << 16) | a
}

#[cfg(test)]
pub mod check {
    //! A reader of the PNG files [`super::encode_rgb`] writes (stored blocks only), for tests.

    /// `(width, height, rgb)` of a PNG written by [`super::encode_rgb`], with every CRC and
    /// the Adler-32 checked.
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
        // Stored deflate blocks after the 2-byte zlib header
        let mut raw = Vec::new();
        let mut p = 2;
        loop {
            let last = z[p] & 1 == 1;
            let len = u16::from_le_bytes([z[p + 1], z[p + 2]]) as usize;
            raw.extend_from_slice(&z[p + 5..p + 5 + len]);
            p += 5 + len;
            if last {
                break;
            }
        }
        if u32::from_be_bytes(z[p..p + 4].try_into().unwrap()) != super::adler32(&raw) {
            return Err("bad Adler-32".into());
        }
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
        // CRC-32 of "123456789" is 0xCBF43926; Adler-32 of "Wikipedia" is 0x11E60398.
        assert_eq!(crc32(b"123456789".iter()), 0xCBF4_3926);
        assert_eq!(adler32(b"Wikipedia"), 0x11E6_0398);
    }

    #[test]
    fn round_trips_through_several_blocks() {
        let (w, h) = (300u32, 100u32);
        let rgb: Vec<u8> = (0..3 * w * h).map(|k| (k * 7 % 251) as u8).collect();
        let png = encode_rgb(w, h, &rgb).unwrap();
        assert_eq!(check::decode_rgb(&png).unwrap(), (w, h, rgb));
        assert!(encode_rgb(0, 1, &[]).is_none());
        assert!(encode_rgb(2, 2, &[0; 11]).is_none());
    }
}
