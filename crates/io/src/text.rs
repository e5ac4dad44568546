//! Input text read with bounds, and excerpts of it for messages.
//!
//! [`read_text`] reads a file whole, but refuses a line longer than
//! [`MAX_LINE_BYTES`] as soon as the part of the file read so far holds
//! one: a corrupted file (2 GiB of NUL bytes) or a file of another kind
//! is refused after its first MiB or two, not read whole and held as one
//! line. [`excerpt`] is what an error quotes of a line: at most
//! [`EXCERPT_CHARS`] characters, control characters escaped.

use crate::InputError;
use std::borrow::Cow;
use std::io::Read;
use std::path::Path;

/// The longest line [`read_text`] accepts (1 MiB). Decks, matrix files,
/// DOF lists and body files have lines of a few hundred bytes at most.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// The most characters of a line an error message quotes.
pub const EXCERPT_CHARS: usize = 80;

/// `line` as an error quotes it: whole when it is short, else its first
/// [`EXCERPT_CHARS`] characters, `...` and its length; control characters
/// (a NUL byte) are shown escaped (`\0`).
pub fn excerpt(line: &str) -> Cow<'_, str> {
    excerpt_of(line, line.len())
}

/// [`excerpt`] of a line of `bytes` bytes that starts with `head`.
fn excerpt_of(head: &str, bytes: usize) -> Cow<'_, str> {
    let line = head;
    let short = bytes == line.len() && line.chars().count() <= EXCERPT_CHARS;
    if short && !line.chars().any(char::is_control) {
        return Cow::Borrowed(line);
    }
    let mut out = String::with_capacity(EXCERPT_CHARS + 32);
    for c in line.chars().take(EXCERPT_CHARS) {
        if c.is_control() {
            out.extend(c.escape_debug());
        } else {
            out.push(c);
        }
    }
    if !short {
        out.push_str(&format!("... ({bytes} bytes)"));
    }
    Cow::Owned(out)
}

/// The longest error message [`shortened`] leaves whole (1000 bytes).
pub const MESSAGE_BYTES: usize = 1000;

/// An error and its causes as one line, `outer: inner: ...`, each cause
/// once (a wrapper that already prints its cause, `"reading the body:
/// {0}"`, is not followed by that cause again) and each [`shortened`]: the
/// message the command line prints and the Python package raises.
pub fn error_chain(error: &(dyn std::error::Error + 'static)) -> String {
    let mut out = String::new();
    let mut cause = Some(error);
    while let Some(c) = cause {
        let text = c.to_string();
        if !out.ends_with(&text) {
            if !out.is_empty() {
                out.push_str(": ");
            }
            out.push_str(&shortened(&text));
        }
        cause = c.source();
    }
    out
}

/// `message`, or its first 600 and last 300 bytes when it is longer than
/// [`MESSAGE_BYTES`], saying how much was left out: what every error of
/// the readers shows, so that no message quotes a huge piece of its input
/// (an unknown TOML key of a megabyte), whichever reader wrote it.
pub fn shortened(message: &str) -> Cow<'_, str> {
    if message.len() <= MESSAGE_BYTES {
        return message.into();
    }
    let mut head = 600;
    while !message.is_char_boundary(head) {
        head -= 1;
    }
    let mut tail = message.len() - 300;
    while !message.is_char_boundary(tail) {
        tail += 1;
    }
    format!(
        "{} [... {} bytes left out ...] {}",
        &message[..head],
        tail - head,
        &message[tail..]
    )
    .into()
}

/// A number of an input file: finite and at most
/// [`LARGEST`](flexbody_linalg::dense_check::LARGEST) in magnitude (Rust's
/// float parsing takes `nan`, `inf` and `1e999` as numbers); the error
/// quotes an [`excerpt`] of `text`.
pub fn finite_number(text: &str) -> Result<f64, String> {
    let largest = flexbody_linalg::dense_check::LARGEST;
    match text.parse::<f64>() {
        Ok(v) if v.abs() <= largest => Ok(v),
        Ok(v) if v.is_finite() => Err(format!("{v:e} is beyond {largest:e} in magnitude")),
        Ok(_) => Err(format!("'{}' is not a finite number", excerpt(text))),
        Err(_) => Err(format!("'{}' is not a number", excerpt(text))),
    }
}

/// Refuses to read `path` unless it is a regular file (or a link to one)
/// or a folder: a device (`/dev/urandom` never ends, `/dev/tty` waits for
/// a user), a pipe (`/dev/stdin`, which a deck's `*INCLUDE` could name)
/// or a socket is not read. A path that does not exist passes: opening it
/// says so.
pub fn regular_file(path: &Path) -> Result<(), InputError> {
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() && !m.is_dir() => Err(InputError::Read {
            path: path.to_path_buf(),
            cause: std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "not a regular file (a device, a pipe or a socket); inputs are read from files",
            ),
        }),
        _ => Ok(()),
    }
}

/// The bytes of the file at `path`; an error names the file and, for a
/// line longer than [`MAX_LINE_BYTES`], the line with an [`excerpt`].
/// Only a regular file is read ([`regular_file`]).
pub fn read_bytes(path: &Path) -> Result<Vec<u8>, InputError> {
    let read_error = |cause| InputError::Read {
        path: path.to_path_buf(),
        cause,
    };
    regular_file(path)?;
    let mut file = std::fs::File::open(path).map_err(read_error)?;
    let size = file.metadata().map_or(0, |m| m.len());
    let mut bytes = Vec::with_capacity(usize::try_from(size).unwrap_or(0).saturating_add(1));
    // Blocks of half the longest line: a line longer than that holds a
    // whole block without a newline, and a block without one is the only
    // place a long line is looked for.
    const BLOCK: usize = MAX_LINE_BYTES / 2;
    let mut checked = 0;
    loop {
        let got = (&mut file)
            .take(BLOCK as u64)
            .read_to_end(&mut bytes)
            .map_err(read_error)?;
        // A block is looked at once the next one is read too, so that a
        // line through it is seen to its end where that is near.
        while bytes.len() - checked >= 2 * BLOCK || (got == 0 && checked < bytes.len()) {
            let end = (checked + BLOCK).min(bytes.len());
            if memchr::memchr(b'\n', &bytes[checked..end]).is_none() {
                long_line(path, &bytes, checked, got == 0)?;
            }
            checked = end;
        }
        if got == 0 {
            return Ok(bytes);
        }
    }
}

/// The file at `path` as text (UTF-8), read by [`read_bytes`].
pub fn read_text(path: &Path) -> Result<String, InputError> {
    String::from_utf8(read_bytes(path)?).map_err(|e| InputError::Read {
        path: path.to_path_buf(),
        cause: std::io::Error::new(std::io::ErrorKind::InvalidData, e.utf8_error()),
    })
}

/// The error for the line through byte `at` of `bytes` when it is longer
/// than [`MAX_LINE_BYTES`] (as far as the file has been read; `whole`
/// when all of it has).
fn long_line(path: &Path, bytes: &[u8], at: usize, whole: bool) -> Result<(), InputError> {
    let start = memchr::memrchr(b'\n', &bytes[..at]).map_or(0, |i| i + 1);
    let end = memchr::memchr(b'\n', &bytes[at..]).map_or(bytes.len(), |i| at + i);
    let length = end - start;
    if length <= MAX_LINE_BYTES {
        return Ok(());
    }
    let line = memchr::memchr_iter(b'\n', &bytes[..start]).count() + 1;
    let head = &bytes[start..start + (4 * EXCERPT_CHARS).min(length)];
    let text = String::from_utf8_lossy(head);
    let at_least = if end == bytes.len() && !whole {
        "at least "
    } else {
        ""
    };
    Err(InputError::Invalid {
        path: path.to_path_buf(),
        line: Some(line),
        message: format!(
            "the line is {at_least}{length} bytes long, more than the {MAX_LINE_BYTES} a line \
             of an input file may have (is this the right file?): '{}'",
            excerpt_of(&text, length)
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_excerpt_keeps_a_short_line_and_cuts_a_long_one() {
        assert_eq!(excerpt("1, 2.0, 3.0"), "1, 2.0, 3.0");
        let long = "x".repeat(5000);
        let e = excerpt(&long);
        assert_eq!(e, format!("{}... (5000 bytes)", "x".repeat(EXCERPT_CHARS)));
        assert_eq!(excerpt("a\0b"), "a\\0b");
        // Cut at a character, not inside one.
        let wide = "\u{e9}".repeat(200);
        assert!(excerpt(&wide).starts_with(&"\u{e9}".repeat(EXCERPT_CHARS)));
    }

    #[test]
    fn a_line_longer_than_the_bound_is_refused_with_its_number_and_an_excerpt() {
        let dir = tempdir("long-line");
        let path = dir.join("k.mtx");
        let long = "9".repeat(MAX_LINE_BYTES + 1);
        std::fs::write(&path, format!("a\nb\n{long}\nc\n")).unwrap();
        let message = read_text(&path).unwrap_err().to_string();
        assert!(
            message.contains("k.mtx:3: the line is 1048577 bytes long"),
            "{message}"
        );
        assert!(message.len() < 400, "{} bytes", message.len());
        // The longest accepted line, at the end of a file without a newline.
        let longest = "9".repeat(MAX_LINE_BYTES);
        std::fs::write(&path, format!("a\n{longest}")).unwrap();
        assert_eq!(read_text(&path).unwrap().len(), MAX_LINE_BYTES + 2);
        // Lines around a block boundary, and an empty file.
        let text = format!("{}\n{}\n", "1".repeat(600_000), "2".repeat(900_000));
        std::fs::write(&path, &text).unwrap();
        assert_eq!(read_text(&path).unwrap(), text);
        std::fs::write(&path, "").unwrap();
        assert_eq!(read_text(&path).unwrap(), "");
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn a_file_of_nul_bytes_is_refused_before_it_is_read_whole() {
        let dir = tempdir("nul");
        let path = dir.join("k.mtx");
        // 64 MiB of NUL bytes, as a sparse file; only the first MiB or two
        // are read.
        let file = std::fs::File::create(&path).unwrap();
        file.set_len(64 << 20).unwrap();
        let e = read_bytes(&path).unwrap_err().to_string();
        assert!(e.contains("k.mtx:1: the line is at least"), "{e}");
        assert!(e.contains("'\\0\\0\\0"), "{e}");
        assert!(e.len() < 500, "{} bytes", e.len());
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn a_long_message_keeps_its_start_and_end() {
        assert_eq!(shortened("short"), "short");
        let long = format!("unknown key `{}`, expected `a`", "\u{e9}".repeat(5000));
        let s = shortened(&long);
        assert!(s.len() < MESSAGE_BYTES + 100, "{}", s.len());
        assert!(s.starts_with("unknown key `") && s.ends_with("`, expected `a`"));
        assert!(s.contains("bytes left out"));
    }

    #[test]
    fn devices_and_pipes_are_not_read() {
        // /dev/urandom would be read without end, /dev/stdin a pipe or a
        // terminal waiting for input.
        for device in ["/dev/urandom", "/dev/null"] {
            let e = read_bytes(Path::new(device)).unwrap_err().to_string();
            assert!(e.contains("not a regular file"), "{e}");
        }
        let e = read_bytes(Path::new("/no/such/file")).unwrap_err();
        assert!(!e.to_string().contains("regular"), "{e}");
    }

    fn tempdir(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("flexbody-text-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }
}
