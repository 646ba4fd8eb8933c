//! Animated GIF encoding with one palette for every frame: the colours are chosen once from all
//! the frames (the most frequent ones; the pictures are mostly flat colours), every pixel is
//! mapped to its nearest palette colour without dithering, so a colour is the same in every
//! frame; each frame after the first stores only the rectangle that changed, the unchanged
//! pixels in it transparent, which keeps an animation of a still view small.

use std::collections::HashMap;

use rayon::prelude::*;

use crate::error::ViewError;

/// One rasterised frame: width, height, straight RGBA bytes.
pub type Rgba = (u32, u32, Vec<u8>);

/// The palette index that means "as in the previous frame".
const TRANSPARENT: u8 = 255;

/// A pixel's colour as one number (alpha ignored: the pictures are opaque).
fn key(p: &[u8]) -> u32 {
    (u32::from(p[0]) << 16) | (u32::from(p[1]) << 8) | u32::from(p[2])
}

/// Up to 255 colours: the most frequent in a sample of every frame's pixels (ties broken by
/// the colour, so the palette does not depend on the order of a hash map).
pub fn palette(frames: &[Rgba]) -> Vec<[u8; 3]> {
    let counts: HashMap<u32, u64> = frames
        .par_iter()
        .map(|(_, _, rgba)| {
            let mut c: HashMap<u32, u64> = HashMap::new();
            let mut last = u32::MAX;
            for p in rgba.chunks_exact(4).step_by(3) {
                let k = key(p);
                // Runs of one colour are common: count them without hashing each pixel.
                if k == last {
                    if let Some(n) = c.get_mut(&k) {
                        *n += 1;
                        continue;
                    }
                }
                *c.entry(k).or_insert(0) += 1;
                last = k;
            }
            c
        })
        .reduce(HashMap::new, |mut a, b| {
            for (k, n) in b {
                *a.entry(k).or_insert(0) += n;
            }
            a
        });
    let mut by_count: Vec<(u32, u64)> = counts.into_iter().collect();
    by_count.sort_unstable_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    by_count
        .into_iter()
        .take(usize::from(TRANSPARENT))
        .map(|(k, _)| [(k >> 16) as u8, (k >> 8) as u8, k as u8])
        .collect()
}

/// The index of the palette colour nearest to `k`.
fn nearest(palette: &[[u8; 3]], k: u32) -> u8 {
    let c = [
        (k >> 16) as i32,
        ((k >> 8) & 0xff) as i32,
        (k & 0xff) as i32,
    ];
    let mut best = (i32::MAX, 0usize);
    for (i, p) in palette.iter().enumerate() {
        let d = [c[0] - p[0] as i32, c[1] - p[1] as i32, c[2] - p[2] as i32];
        // Weighted for the eye: green counts most, blue least.
        let dist = 3 * d[0] * d[0] + 4 * d[1] * d[1] + 2 * d[2] * d[2];
        if dist < best.0 {
            best = (dist, i);
        }
    }
    best.1 as u8
}

/// A frame's pixels as palette indices.
fn indexed(palette: &[[u8; 3]], exact: &HashMap<u32, u8>, rgba: &[u8]) -> Vec<u8> {
    let mut cache: HashMap<u32, u8> = HashMap::new();
    let (mut last, mut last_index) = (u32::MAX, 0u8);
    rgba.chunks_exact(4)
        .map(|p| {
            let k = key(p);
            if k != last {
                last = k;
                last_index = match exact.get(&k) {
                    Some(i) => *i,
                    None => *cache.entry(k).or_insert_with(|| nearest(palette, k)),
                };
            }
            last_index
        })
        .collect()
}

/// Encodes frames (all of one size) as a looping GIF, `delay_cs` hundredths of a second each.
pub fn encode(frames: &[Rgba], delay_cs: u16) -> Result<Vec<u8>, ViewError> {
    let render = |e: gif::EncodingError| ViewError::Render(e.to_string());
    let Some((w, h, _)) = frames.first() else {
        return Err(ViewError::Render(
            "an animation needs at least one frame".into(),
        ));
    };
    if frames.iter().any(|(fw, fh, _)| (fw, fh) != (w, h)) {
        return Err(ViewError::Render(
            "the frames of an animation must be of one size".into(),
        ));
    }
    let too_large = || ViewError::Render(format!("GIF size {w} x {h} is too large"));
    let w16 = u16::try_from(*w).map_err(|_| too_large())?;
    let h16 = u16::try_from(*h).map_err(|_| too_large())?;
    let colours = palette(frames);
    let exact: HashMap<u32, u8> = colours
        .iter()
        .enumerate()
        .map(|(i, c)| (key(&[c[0], c[1], c[2], 255]), i as u8))
        .collect();
    let indices: Vec<Vec<u8>> = frames
        .par_iter()
        .map(|(_, _, rgba)| indexed(&colours, &exact, rgba))
        .collect();
    // The global palette: the colours, padded to 256 entries (the last one is transparent).
    let mut table: Vec<u8> = colours.iter().flatten().copied().collect();
    table.resize(256 * 3, 0);
    let mut bytes = Vec::new();
    {
        let mut encoder = gif::Encoder::new(&mut bytes, w16, h16, &table).map_err(render)?;
        encoder.set_repeat(gif::Repeat::Infinite).map_err(render)?;
        let width = usize::from(w16);
        let mut previous: Option<&Vec<u8>> = None;
        for px in &indices {
            let mut frame = match previous {
                None => gif::Frame::from_indexed_pixels(w16, h16, px.clone(), None),
                Some(prev) => delta(prev, px, width, usize::from(h16)),
            };
            frame.delay = delay_cs;
            frame.dispose = gif::DisposalMethod::Keep;
            encoder.write_frame(&frame).map_err(render)?;
            previous = Some(px);
        }
    }
    Ok(bytes)
}

/// The part of `next` that differs from `prev`: its bounding rectangle, with the pixels that
/// did not change transparent (a one-pixel transparent frame when nothing changed).
fn delta(prev: &[u8], next: &[u8], width: usize, height: usize) -> gif::Frame<'static> {
    let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
    for y in 0..height {
        let row = y * width..(y + 1) * width;
        let (a, b) = (&prev[row.clone()], &next[row]);
        if a == b {
            continue;
        }
        let first = a.iter().zip(b).position(|(p, q)| p != q).unwrap_or(0);
        let last = width
            - 1
            - a.iter()
                .rev()
                .zip(b.iter().rev())
                .position(|(p, q)| p != q)
                .unwrap_or(0);
        x0 = x0.min(first);
        x1 = x1.max(last);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if x0 == usize::MAX {
        return gif::Frame::from_indexed_pixels(1, 1, vec![TRANSPARENT], Some(TRANSPARENT));
    }
    let (fw, fh) = (x1 - x0 + 1, y1 - y0 + 1);
    let mut buf = Vec::with_capacity(fw * fh);
    for y in y0..=y1 {
        for x in x0..=x1 {
            let i = y * width + x;
            buf.push(if prev[i] == next[i] {
                TRANSPARENT
            } else {
                next[i]
            });
        }
    }
    // The sizes fit: they are at most the picture's, which fits in u16.
    let mut frame = gif::Frame::from_indexed_pixels(fw as u16, fh as u16, buf, Some(TRANSPARENT));
    frame.left = x0 as u16;
    frame.top = y0 as u16;
    frame
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solid(w: u32, h: u32, c: [u8; 3]) -> Rgba {
        let px: Vec<u8> = (0..w * h).flat_map(|_| [c[0], c[1], c[2], 255]).collect();
        (w, h, px)
    }

    #[test]
    fn frames_decode_to_what_was_encoded_with_one_palette() {
        let mut a = solid(20, 10, [10, 20, 30]);
        let mut b = a.clone();
        // A red square moves: in frame a at x 2..5, in frame b at x 6..9.
        for y in 3..6 {
            for x in 2..5 {
                a.2[(y * 20 + x) * 4..(y * 20 + x) * 4 + 3].copy_from_slice(&[250, 0, 0]);
            }
            for x in 6..9 {
                b.2[(y * 20 + x) * 4..(y * 20 + x) * 4 + 3].copy_from_slice(&[250, 0, 0]);
            }
        }
        let c = b.clone();
        let bytes = encode(&[a.clone(), b.clone(), c], 10).expect("encodes");
        let mut options = gif::DecodeOptions::new();
        options.set_color_output(gif::ColorOutput::Indexed);
        let mut d = options.read_info(bytes.as_slice()).expect("a GIF");
        let global = d.global_palette().expect("a global palette").to_vec();
        let mut canvas = vec![0u8; 200];
        let mut seen = Vec::new();
        while let Some(f) = d.read_next_frame().expect("a frame") {
            assert!(f.palette.is_none(), "a frame with its own palette");
            for y in 0..f.height as usize {
                for x in 0..f.width as usize {
                    let i = f.buffer[y * f.width as usize + x];
                    if Some(i) != f.transparent {
                        canvas[(f.top as usize + y) * 20 + f.left as usize + x] = i;
                    }
                }
            }
            seen.push(canvas.clone());
        }
        assert_eq!(seen.len(), 3);
        let rgb = |i: u8| &global[i as usize * 3..i as usize * 3 + 3];
        for (frame, want) in seen.iter().zip([&a, &b, &b]) {
            for (i, px) in frame.iter().enumerate() {
                assert_eq!(rgb(*px), &want.2[i * 4..i * 4 + 3]);
            }
        }
    }
}
