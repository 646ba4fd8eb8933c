//! Arrow IPC files (feather v2, uncompressed, LZ4- or zstd-compressed, dictionary-encoded or
//! not) checked before they are decoded.
//!
//! [`read_schema`] and [`read_batches`] check the framing (the `ARROW1` magic at both ends and a
//! footer that fits), then every size the file declares (blocks inside the file, buffers inside
//! their block, row counts and uncompressed lengths no larger than the bytes could hold: an LZ4
//! buffer at most [`MAX_EXPANSION`] times its size, a zstd buffer at most what its frame's block
//! headers can produce, and all buffers together at most [`MAX_TOTAL_EXPANSION`] times the file
//! plus 4 GiB),
//! and only then run the Arrow decoder, with a panic inside it turned into an error as a last
//! resort.

use std::io::Cursor;

use arrow_array::RecordBatch;
use arrow_ipc::reader::FileReader;
use arrow_schema::SchemaRef;

/// Why the bytes are not a readable Arrow IPC file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Corrupt {
    /// What is wrong, e.g. "block 0 declares 4294967296 rows in a body of 912 bytes".
    pub reason: String,
}

impl std::fmt::Display for Corrupt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.reason)
    }
}

impl std::error::Error for Corrupt {}

fn corrupt(reason: impl Into<String>) -> Corrupt {
    Corrupt {
        reason: reason.into(),
    }
}

/// LZ4 cannot expand data more than about 255-fold; a buffer declaring more is corrupt.
pub const MAX_EXPANSION: u64 = 256;

/// Most uncompressed bytes all the compressed buffers of a file may declare together, as a
/// multiple of the file's length (plus [`TOTAL_SLACK`]): zstd can legitimately expand a run of
/// one value thousands of times (a 128 KiB block from 4 bytes), so single buffers may go past
/// [`MAX_EXPANSION`], but a file never makes the decoder allocate more than this. (A run's
/// predictions table repeats each log's boxes once per program: the library's 97 programs
/// compress about 380-fold.)
pub const MAX_TOTAL_EXPANSION: u64 = 1024;

/// Uncompressed bytes every file may declare beyond [`MAX_TOTAL_EXPANSION`] times its length.
const TOTAL_SLACK: u64 = 4 << 30;

/// The largest block a zstd frame holds, uncompressed (RFC 8878, `Block_Maximum_Size`).
const ZSTD_MAX_BLOCK: u64 = 128 << 10;

/// The file's schema, read from its footer after the framing checks.
pub fn read_schema(bytes: &[u8]) -> Result<SchemaRef, Corrupt> {
    check_framing(bytes)?;
    guard(|| FileReader::try_new(Cursor::new(bytes), None).map(|r| r.schema()))?
        .map_err(|e| corrupt(e.to_string()))
}

/// Every record batch of the file, keeping only the columns of `projection` (in that order;
/// `None` keeps all), after checking the framing and every declared size.
pub fn read_batches(
    bytes: &[u8],
    projection: Option<Vec<usize>>,
) -> Result<Vec<RecordBatch>, Corrupt> {
    check_framing(bytes)?;
    check_declared_sizes(bytes)?;
    guard(|| {
        let reader = FileReader::try_new(Cursor::new(bytes), projection)?;
        reader.collect::<Result<Vec<RecordBatch>, _>>()
    })?
    .map_err(|e| corrupt(e.to_string()))
}

/// The magic bytes at both ends and a footer length that fits in the file.
fn check_framing(bytes: &[u8]) -> Result<(), Corrupt> {
    if bytes.len() < 12 || &bytes[..6] != b"ARROW1" {
        return Err(corrupt(
            "the file does not start with the Arrow magic bytes `ARROW1`",
        ));
    }
    let footer_fits = read_i32(bytes, bytes.len() - 10)
        .and_then(|l| usize::try_from(l).ok())
        .is_some_and(|l| l + 10 + 8 <= bytes.len());
    if &bytes[bytes.len() - 6..] != b"ARROW1" || !footer_fits {
        return Err(corrupt(
            "the file does not end with an Arrow IPC footer (cut short?)",
        ));
    }
    Ok(())
}

/// Checks the sizes a file declares before the Arrow decoder trusts them: every record batch
/// block lies inside the file, every buffer inside its block, no batch declares more rows, and no
/// compressed buffer more uncompressed bytes, than its compressed size allows.
fn check_declared_sizes(bytes: &[u8]) -> Result<(), Corrupt> {
    let n = bytes.len();
    let footer_len = read_i32(bytes, n.wrapping_sub(10)).unwrap_or(-1);
    let footer_start = usize::try_from(footer_len)
        .ok()
        .and_then(|l| n.checked_sub(10 + l))
        .ok_or_else(|| corrupt("bad footer length"))?;
    let footer = arrow_ipc::root_as_footer(&bytes[footer_start..n - 10])
        .map_err(|e| corrupt(format!("bad footer: {e}")))?;
    let total_limit = (n as u64)
        .saturating_mul(MAX_TOTAL_EXPANSION)
        .saturating_add(TOTAL_SLACK);
    let mut total = 0u64;
    let blocks = footer.recordBatches().into_iter().flatten();
    let dictionaries = footer.dictionaries().into_iter().flatten();
    for (i, block) in blocks.chain(dictionaries).enumerate() {
        let range = |what: &str| corrupt(format!("block {i}: {what} lies outside the file"));
        let offset = usize::try_from(block.offset()).map_err(|_| range("offset"))?;
        let meta_len = usize::try_from(block.metaDataLength()).map_err(|_| range("metadata"))?;
        let body_len = usize::try_from(block.bodyLength()).map_err(|_| range("body"))?;
        let body_start = offset
            .checked_add(meta_len)
            .ok_or_else(|| range("metadata"))?;
        let body_end = body_start
            .checked_add(body_len)
            .filter(|&e| e <= n)
            .ok_or_else(|| range("body"))?;
        let meta = &bytes[offset..body_start];
        // Metadata: [0xFFFFFFFF continuation] i32 length, then the flatbuffer message.
        let skip = if meta.get(..4) == Some(&[0xFF; 4]) {
            8
        } else {
            4
        };
        let message = meta
            .get(skip..)
            .and_then(|m| arrow_ipc::root_as_message(m).ok())
            .ok_or_else(|| corrupt(format!("block {i}: unreadable message header")))?;
        let Some(batch) = message
            .header_as_record_batch()
            .or_else(|| message.header_as_dictionary_batch().and_then(|d| d.data()))
        else {
            continue;
        };
        let max_len = (body_len as u64).saturating_mul(MAX_EXPANSION) + 1024;
        let lengths = std::iter::once(batch.length()).chain(
            batch
                .nodes()
                .into_iter()
                .flatten()
                .map(|node| node.length()),
        );
        for len in lengths {
            if u64::try_from(len).map_or(true, |l| l > max_len) {
                return Err(corrupt(format!(
                    "block {i} declares {len} rows in a body of {body_len} bytes"
                )));
            }
        }
        let codec = batch.compression().map(|c| c.codec());
        for buf in batch.buffers().into_iter().flatten() {
            let start = usize::try_from(buf.offset())
                .ok()
                .and_then(|o| o.checked_add(body_start));
            let len = usize::try_from(buf.length()).ok();
            let (Some(start), Some(len)) = (start, len) else {
                return Err(corrupt(format!(
                    "block {i}: negative buffer offset or length"
                )));
            };
            if start.checked_add(len).is_none_or(|e| e > body_end) {
                return Err(corrupt(format!(
                    "block {i}: a buffer lies outside its body"
                )));
            }
            let Some(codec) = codec.filter(|_| len >= 8) else {
                continue;
            };
            let declared = read_i64(bytes, start).unwrap_or(-1);
            if declared == -1 {
                continue; // stored uncompressed
            }
            let data = &bytes[start + 8..start + len];
            let limit = match codec {
                arrow_ipc::CompressionType::LZ4_FRAME => {
                    (len as u64).saturating_mul(MAX_EXPANSION) + 1024
                }
                arrow_ipc::CompressionType::ZSTD => zstd_bound(data).map_err(|e| {
                    corrupt(format!("block {i}: a zstd buffer of {len} bytes: {e}"))
                })?,
                _ => continue, // the decoder rejects other codecs itself
            };
            let declared_ok = u64::try_from(declared).ok().filter(|&d| d <= limit);
            let Some(d) = declared_ok else {
                return Err(corrupt(format!(
                    "block {i}: a compressed buffer of {len} bytes declares {declared} uncompressed bytes"
                )));
            };
            total = total.saturating_add(d);
            if total > total_limit {
                return Err(corrupt(format!(
                    "the compressed buffers declare more than {total_limit} uncompressed bytes \
                     in all, over {MAX_TOTAL_EXPANSION} times the file's {n} bytes"
                )));
            }
        }
    }
    Ok(())
}

/// The most bytes the zstd frames of `data` can decompress to, read from their headers without
/// decompressing (RFC 8878): a raw block gives its size, an RLE block its repeat count, a
/// compressed block at most 128 KiB, a skippable frame nothing; a frame that declares its
/// content size gives at most that. An error when the frames are cut short or malformed.
pub fn zstd_bound(data: &[u8]) -> Result<u64, String> {
    let mut at = 0usize;
    let mut total = 0u64;
    let cut = || "its zstd frame is cut short".to_string();
    while at < data.len() {
        let magic = data
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .ok_or_else(cut)?;
        at += 4;
        if magic & 0xFFFF_FFF0 == 0x184D_2A50 {
            let size = data
                .get(at..at + 4)
                .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .ok_or_else(cut)?;
            at = at.checked_add(4 + size as usize).ok_or_else(cut)?;
            continue;
        }
        if magic != 0xFD2F_B528 {
            return Err(format!("not a zstd frame (magic {magic:#010x})"));
        }
        let descriptor = *data.get(at).ok_or_else(cut)?;
        at += 1;
        let single_segment = descriptor & 0x20 != 0;
        let checksum = descriptor & 0x04 != 0;
        let dictionary_bytes = [0, 1, 2, 4][usize::from(descriptor & 0x03)];
        let content_bytes = match descriptor >> 6 {
            0 => usize::from(single_segment),
            1 => 2,
            2 => 4,
            _ => 8,
        };
        at += usize::from(!single_segment) + dictionary_bytes;
        let content = data.get(at..at + content_bytes).ok_or_else(cut)?;
        at += content_bytes;
        let declared_content = match content_bytes {
            0 => None,
            _ => {
                let mut w = [0u8; 8];
                w[..content_bytes].copy_from_slice(content);
                let v = u64::from_le_bytes(w);
                Some(if content_bytes == 2 { v + 256 } else { v })
            }
        };
        let mut frame = 0u64;
        loop {
            let h = data.get(at..at + 3).ok_or_else(cut)?;
            at += 3;
            let header = u32::from(h[0]) | u32::from(h[1]) << 8 | u32::from(h[2]) << 16;
            let last = header & 1 != 0;
            let size = u64::from(header >> 3);
            let (stored, produced) = match (header >> 1) & 3 {
                0 => (size, size),
                1 => (1, size),
                2 => (size, ZSTD_MAX_BLOCK),
                _ => return Err("a zstd block of the reserved type".to_string()),
            };
            if produced > ZSTD_MAX_BLOCK {
                return Err(format!("a zstd block of {produced} bytes, over 128 KiB"));
            }
            at = at.checked_add(stored as usize).ok_or_else(cut)?;
            if at > data.len() {
                return Err(cut());
            }
            frame += produced;
            if last {
                break;
            }
        }
        if checksum {
            at += 4;
        }
        total = total.saturating_add(declared_content.map_or(frame, |c| c.min(frame)));
    }
    if at > data.len() {
        return Err(cut());
    }
    Ok(total)
}

fn read_i32(bytes: &[u8], at: usize) -> Option<i32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(i32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

fn read_i64(bytes: &[u8], at: usize) -> Option<i64> {
    let b = bytes.get(at..at.checked_add(8)?)?;
    let mut w = [0u8; 8];
    w.copy_from_slice(b);
    Some(i64::from_le_bytes(w))
}

/// Panics the Arrow decoder raised inside [`guard`] since the process started.
static GUARDED_PANICS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// How many times the Arrow decoder panicked on a file and the panic became a [`Corrupt`]
/// error (its message unprinted). For fuzzing: a reader that validates first should keep this
/// at zero.
pub fn guarded_panics() -> usize {
    GUARDED_PANICS.load(std::sync::atomic::Ordering::Relaxed)
}

std::thread_local! {
    /// Whether this thread is inside [`guard`]: a panic there is an error, not a message.
    static GUARDED: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Installs, once, a panic hook that stays silent for a panic inside [`guard`] on this thread and
/// hands every other panic to the hook that was there before.
fn quiet_in_guard() {
    static INSTALL: std::sync::Once = std::sync::Once::new();
    INSTALL.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !GUARDED.with(|g| g.get()) {
                previous(info);
            }
        }));
    });
}

/// Runs the Arrow decoder, turning a panic inside it (possible on corrupt input in some arrow
/// versions) into a [`Corrupt`], so that no input can crash the program; the panic's own message
/// is not printed (the user sees the error, which names the file).
fn guard<T>(f: impl FnOnce() -> T) -> Result<T, Corrupt> {
    quiet_in_guard();
    let was = GUARDED.with(|g| g.replace(true));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    GUARDED.with(|g| g.set(was));
    if result.is_err() {
        GUARDED_PANICS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    }
    result.map_err(|_| corrupt("the Arrow decoder rejected the file's contents"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use arrow_array::{Float64Array, Int64Array};
    use arrow_ipc::writer::{FileWriter, IpcWriteOptions};
    use std::sync::Arc;

    /// A two-column table of `rows` rows as an Arrow IPC file, compressed with `codec` or not.
    fn table_with(rows: i64, codec: Option<arrow_ipc::CompressionType>) -> Vec<u8> {
        let ts: Int64Array = (0..rows).map(|i| i * 100_000_000).collect();
        let x: Float64Array = (0..rows).map(|i| (i as f64).sin()).collect();
        let batch = RecordBatch::try_from_iter([
            ("timestamp_ns", Arc::new(ts) as _),
            ("x", Arc::new(x) as _),
        ])
        .expect("batch");
        let options = IpcWriteOptions::default()
            .try_with_compression(codec)
            .expect("options");
        let mut out = Vec::new();
        let mut w =
            FileWriter::try_new_with_options(&mut out, &batch.schema(), options).expect("writer");
        w.write(&batch).expect("write");
        w.finish().expect("finish");
        drop(w);
        out
    }

    /// [`table_with`], LZ4-compressed or not.
    fn table(rows: i64, lz4: bool) -> Vec<u8> {
        table_with(rows, lz4.then_some(arrow_ipc::CompressionType::LZ4_FRAME))
    }

    #[test]
    fn valid_files_read_and_projection_keeps_the_order() {
        for lz4 in [false, true] {
            let bytes = table(500, lz4);
            let schema = read_schema(&bytes).expect("schema");
            assert_eq!(schema.fields().len(), 2);
            let batches = read_batches(&bytes, Some(vec![1])).expect("batches");
            let rows: usize = batches.iter().map(|b| b.num_rows()).sum();
            assert_eq!(rows, 500);
            assert_eq!(batches[0].schema().field(0).name(), "x");
        }
    }

    #[test]
    fn framing_errors_say_what_is_missing() {
        let bytes = table(10, true);
        let err = read_batches(b"timestamp_ns,x\n1,2\n", None).expect_err("CSV");
        assert!(err.reason.contains("magic bytes"), "{err}");
        let err = read_batches(&bytes[..bytes.len() / 2], None).expect_err("cut short");
        assert!(err.reason.contains("footer"), "{err}");
    }

    #[test]
    fn absurd_declared_sizes_are_errors() {
        // Every aligned word of the file set to 2^50 in turn: each read ends (no abort, no
        // panic: the test would die), and the size checks name what they caught.
        let bytes = table(2_000, true);
        let (mut rows, mut uncompressed, mut outside) = (0, 0, 0);
        for at in (8..bytes.len() - 16).step_by(8) {
            let mut bad = bytes.clone();
            bad[at..at + 8].copy_from_slice(&(1i64 << 50).to_le_bytes());
            if let Err(e) = read_batches(&bad, None) {
                rows += usize::from(e.reason.contains("rows in a body"));
                uncompressed += usize::from(e.reason.contains("uncompressed bytes"));
                outside += usize::from(e.reason.contains("outside"));
            }
        }
        assert!(rows > 0, "no row count blow-up caught");
        assert!(uncompressed > 0, "no uncompressed-length blow-up caught");
        assert!(outside > 0, "no offset or length blow-up caught");
    }

    #[test]
    fn a_buffer_declared_stored_uncompressed_is_an_error_counted_not_printed() {
        // Every aligned word set to -1 ("stored uncompressed") in turn: the LZ4 bytes are then
        // taken as raw values. Each read ends in a value or an error; a panic inside the
        // decoder is counted by `guarded_panics` and its message is not printed.
        let bytes = table(2_000, true);
        let before = guarded_panics();
        let mut errors = 0;
        for at in (8..bytes.len() - 16).step_by(8) {
            let mut bad = bytes.clone();
            bad[at..at + 8].copy_from_slice(&(-1i64).to_le_bytes());
            errors += usize::from(read_batches(&bad, None).is_err());
        }
        eprintln!(
            "{errors} errors, {} decoder panics caught",
            guarded_panics() - before
        );
        assert!(errors > 0);
    }

    #[test]
    fn a_panic_inside_the_guard_is_an_error_and_its_message_is_not_printed() {
        const CHILD: &str = "SCENALOG_INPUT_GUARD_CHILD";
        let name =
            "arrow::tests::a_panic_inside_the_guard_is_an_error_and_its_message_is_not_printed";
        if std::env::var_os(CHILD).is_some() {
            let before = guarded_panics();
            let caught = guard(|| -> () { panic!("decoder exploded inside") });
            assert!(caught.is_err());
            assert_eq!(guarded_panics(), before + 1);
            // Outside the guard, a panic is printed as always.
            let outside = std::thread::spawn(|| panic!("a bug outside")).join();
            assert!(outside.is_err());
            return;
        }
        let exe = std::env::current_exe().expect("the test binary");
        let out = std::process::Command::new(exe)
            .args([name, "--exact", "--nocapture", "--test-threads=1"])
            .env(CHILD, "1")
            .output()
            .expect("run the child");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        assert!(!stderr.contains("decoder exploded"), "printed: {stderr}");
        assert!(stderr.contains("a bug outside"), "{stderr}");
    }

    #[test]
    fn zstd_files_read() {
        let bytes = table_with(5_000, Some(arrow_ipc::CompressionType::ZSTD));
        assert!(bytes.len() < table(5_000, false).len(), "compressed");
        let batches = read_batches(&bytes, None).expect("zstd batches");
        let rows: usize = batches.iter().map(|b| b.num_rows()).sum();
        assert_eq!(rows, 5_000);
    }

    #[test]
    fn absurd_declared_sizes_are_errors_in_zstd_files_too() {
        // As for LZ4: every aligned word set to 2^50 in turn, and also to a size just past what
        // the buffer's zstd blocks can produce; each read ends, the checks name what they caught.
        let bytes = table_with(4_000, Some(arrow_ipc::CompressionType::ZSTD));
        let mut uncompressed = 0;
        for at in (8..bytes.len() - 16).step_by(8) {
            let mut bad = bytes.clone();
            bad[at..at + 8].copy_from_slice(&(1i64 << 50).to_le_bytes());
            if let Err(e) = read_batches(&bad, None) {
                uncompressed += usize::from(e.reason.contains("uncompressed bytes"));
            }
        }
        assert!(uncompressed > 0, "no uncompressed-length blow-up caught");
    }

    #[test]
    fn a_zstd_bound_covers_the_data_and_cut_frames_are_errors() {
        let bytes = table_with(4_000, Some(arrow_ipc::CompressionType::ZSTD));
        // The first zstd frame of the file, after its 8-byte length prefix.
        let magic = [0x28, 0xB5, 0x2F, 0xFD];
        let at = bytes
            .windows(4)
            .position(|w| w == magic)
            .expect("a zstd frame");
        let declared = read_i64(&bytes, at - 8).expect("length");
        let frame_end = (at..bytes.len())
            .rev()
            .find(|&end| zstd_bound(&bytes[at..end]).is_ok())
            .expect("a whole frame");
        let bound = zstd_bound(&bytes[at..frame_end]).expect("bound");
        assert!(bound >= declared as u64, "{bound} < {declared}");
        assert!(zstd_bound(&bytes[at..at + 6]).is_err(), "cut short");
        assert!(zstd_bound(b"not zstd").is_err());
        // One RLE block of 1000 bytes, last: header (1000 << 3) | (1 << 1) | 1, then the byte.
        let header = (1000u32 << 3) | 0b11;
        let mut rle = vec![0x28, 0xB5, 0x2F, 0xFD, 0x00, 0x00];
        rle.extend_from_slice(&header.to_le_bytes()[..3]);
        rle.push(7);
        assert_eq!(zstd_bound(&rle), Ok(1000));
    }
}
