//! One fuzz input as several files: a deck and its `*INCLUDE`s, a model
//! file and its mesh, K, M and the DOF list, a body folder.
//!
//! The input is text; a line `@@@ name` starts the file `name`, and what
//! comes before the first such line is the target's main file. Names keep
//! ASCII letters, digits, `.`, `_` and `-` (anything else becomes `_`), so
//! every file lands in the bundle's own folder; a name given twice adds to
//! the same file. The folder is a fresh one under `/dev/shm` (a tmpfs)
//! for each input, so no file of an earlier input is seen.

use std::path::{Path, PathBuf};

/// The line that starts a file of the bundle.
pub const FILE_MARK: &str = "@@@ ";

/// At most this many files are written; later ones join the last.
const MAX_FILES: usize = 16;

/// The files of one input, written to a private folder.
pub struct Bundle {
    /// The folder holding the files (removed and written anew per input).
    pub dir: PathBuf,
    /// The main file: the part before the first `@@@` line.
    pub main: PathBuf,
    /// The names of the files written, the main file first.
    pub names: Vec<String>,
}

impl Bundle {
    /// Writes the files of `data` into this process's folder, the main one
    /// as `main_name`. Panics only if the tmpfs folder cannot be written,
    /// which is the harness's fault, not the reader's.
    pub fn unpack(data: &[u8], main_name: &str) -> Bundle {
        let dir = folder();
        if dir.exists() {
            std::fs::remove_dir_all(&dir).expect("clear the fuzz folder");
        }
        std::fs::create_dir_all(&dir).expect("create the fuzz folder");
        let mut names: Vec<String> = vec![main_name.to_string()];
        let mut contents: Vec<Vec<u8>> = vec![Vec::new()];
        let mut current = 0;
        for line in data.split_inclusive(|&b| b == b'\n') {
            if let Some(name) = line.strip_prefix(FILE_MARK.as_bytes()) {
                let name = clean_name(name);
                current = match names.iter().position(|n| *n == name) {
                    Some(i) => i,
                    None if names.len() < MAX_FILES => {
                        names.push(name);
                        contents.push(Vec::new());
                        names.len() - 1
                    }
                    None => names.len() - 1,
                };
                continue;
            }
            contents[current].extend_from_slice(line);
        }
        for (name, bytes) in names.iter().zip(&contents) {
            std::fs::write(dir.join(name), bytes).expect("write a fuzz file");
        }
        Bundle {
            main: dir.join(main_name),
            dir,
            names,
        }
    }

    /// The path of the file `name` in the bundle's folder.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Whether the input has a file `name`.
    pub fn has(&self, name: &str) -> bool {
        self.names.iter().any(|n| n == name)
    }
}

/// This process's folder: `/dev/shm/flexbody-fuzz-<pid>` (the system
/// temporary folder where there is no `/dev/shm`).
fn folder() -> PathBuf {
    let base = Path::new("/dev/shm");
    let base = if base.is_dir() {
        base.to_path_buf()
    } else {
        std::env::temp_dir()
    };
    base.join(format!("flexbody-fuzz-{}", std::process::id()))
}

/// A file name from the bytes after `@@@ `: one path component, never
/// `.` or `..`.
fn clean_name(raw: &[u8]) -> String {
    let name: String = raw
        .iter()
        .take(64)
        .filter(|&&b| b != b'\n' && b != b'\r')
        .map(|&b| {
            if b.is_ascii_alphanumeric() || b == b'.' || b == b'_' || b == b'-' {
                b as char
            } else {
                '_'
            }
        })
        .collect();
    if name.chars().all(|c| c == '.') {
        format!("_{name}")
    } else {
        name
    }
}
