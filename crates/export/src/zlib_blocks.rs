//! VTK's zlib-compressed array layout (`vtkZLibDataCompressor`, `UInt64`
//! headers), as binary `.vtu` files store each array: the bytes are cut
//! into blocks of `block_size` (the last one may be shorter), each block is
//! compressed on its own as a zlib stream, and the array is written as
//!
//! ```text
//! [blocks, block_size, last_block_size, compressed_size_1 .. compressed_size_n]  (u64, little-endian)
//! compressed block 1 .. compressed block n
//! ```
//!
//! where `last_block_size` is the uncompressed size of the last block. An
//! empty array is the header `[0, block_size, 0]` alone.

use flate2::write::ZlibEncoder;
use flate2::Compression;
use rayon::prelude::*;
use std::io::Write;

/// The zlib level: the fastest. Mode shapes and stresses are mostly
/// mantissa bits, which higher levels hardly shrink further (figures in
/// `docs/performance.md`).
const LEVEL: u32 = 1;

/// Each of `arrays` in the layout of the module docs, with blocks of
/// `block_size` bytes; the blocks of all arrays are compressed in parallel.
pub(crate) fn compress_all(arrays: &[Vec<u8>], block_size: usize) -> Vec<Vec<u8>> {
    let blocks: Vec<&[u8]> = arrays.iter().flat_map(|b| b.chunks(block_size)).collect();
    let compressed: Vec<Vec<u8>> = blocks.par_iter().map(|b| compress(b)).collect();
    let mut compressed = compressed.into_iter();
    arrays
        .iter()
        .map(|bytes| {
            let mine: Vec<Vec<u8>> = compressed
                .by_ref()
                .take(bytes.len().div_ceil(block_size))
                .collect();
            let last = match bytes.len() % block_size {
                0 if bytes.is_empty() => 0,
                0 => block_size,
                partial => partial,
            };
            let sizes = mine.iter().map(Vec::len);
            let header: Vec<usize> = [mine.len(), block_size, last]
                .into_iter()
                .chain(sizes.clone())
                .collect();
            let mut out = Vec::with_capacity(8 * header.len() + sizes.sum::<usize>());
            for h in header {
                out.extend_from_slice(&(h as u64).to_le_bytes());
            }
            for c in &mine {
                out.extend_from_slice(c);
            }
            out
        })
        .collect()
}

/// One block as a zlib stream.
fn compress(block: &[u8]) -> Vec<u8> {
    let mut encoder =
        ZlibEncoder::new(Vec::with_capacity(block.len() / 2), Compression::new(LEVEL));
    // Writing into a Vec cannot fail.
    let _ = encoder.write_all(block);
    encoder.finish().unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use flate2::read::ZlibDecoder;
    use std::io::Read;

    fn u64_at(b: &[u8], i: usize) -> usize {
        u64::from_le_bytes(b[8 * i..8 * i + 8].try_into().unwrap()) as usize
    }

    /// Decodes the layout back, reading the header as the module docs say.
    fn decode(b: &[u8]) -> (Vec<u8>, usize, usize) {
        let (n, size, last) = (u64_at(b, 0), u64_at(b, 1), u64_at(b, 2));
        let mut at = 8 * (3 + n);
        let mut out = Vec::new();
        for k in 0..n {
            let c = u64_at(b, 3 + k);
            ZlibDecoder::new(&b[at..at + c])
                .read_to_end(&mut out)
                .unwrap();
            at += c;
        }
        assert_eq!(at, b.len(), "the blocks fill the array");
        (out, size, last)
    }

    #[test]
    fn blocks_decode_to_the_bytes_with_the_sizes_in_the_header() {
        let full: Vec<u8> = (0..40u32).flat_map(|i| (i * i).to_le_bytes()).collect();
        let exact: Vec<u8> = (0..64).collect();
        let arrays = vec![full.clone(), Vec::new(), exact.clone(), vec![7]];
        let encoded = compress_all(&arrays, 32);
        assert_eq!(encoded.len(), 4);
        // 160 bytes: 5 blocks of 32; 0 bytes: none; 64: two full; 1: one of 1.
        let expected = [(5, 32), (0, 0), (2, 32), (1, 1)];
        for ((bytes, e), (blocks, last)) in arrays.iter().zip(&encoded).zip(expected) {
            assert_eq!(u64_at(e, 0), blocks);
            let (decoded, size, last_size) = decode(e);
            assert_eq!(&decoded, bytes);
            assert_eq!((size, last_size), (32, last));
        }
    }
}
