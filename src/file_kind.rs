//! What kind of file a command was given, so that a command handed another
//! kind of file (a deck where a model file belongs, a model file where a
//! reduced body belongs) says what it got and what it takes, instead of
//! passing on its parser's first complaint.
//!
//! The kind comes from the first lines of the file where they are
//! unmistakable (a deck's `*KEYWORD`, a JSON `{`, a SID's `part`, a Matrix
//! Market banner), else from the extension, else from a TOML-looking line.
//! Only a recognised kind the command does not take is refused here: a file
//! of the right kind, or of no recognisable kind, goes on to its reader and
//! gets that reader's messages.

use crate::export;
use std::io::Read;
use std::path::{Path, PathBuf};

/// The kinds of file flexbody reads or writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A model file (TOML).
    ModelFile,
    /// An Abaqus/CalculiX input deck.
    Deck,
    /// CalculiX's matrix output (`job.sti`).
    CalculixMatrices,
    /// A Matrix Market matrix (`.mtx`).
    MatrixMarket,
    /// A reduced body as one JSON file.
    BodyJson,
    /// A JSON file without the reduced-body format tag.
    Json,
    /// A reduced body as SID (Standard Input Data).
    Sid,
    /// A reduced body as a folder of Matrix Market files, or its `index.json`.
    MtxFolder,
    /// MBDyn's modal FEM file, which flexbody writes but does not read.
    MbdynFem,
}

impl FileKind {
    /// The kind as a noun phrase: "a CalculiX/Abaqus deck".
    pub fn description(self) -> &'static str {
        match self {
            FileKind::ModelFile => "a model file (TOML)",
            FileKind::Deck => "a CalculiX/Abaqus deck",
            FileKind::CalculixMatrices => "CalculiX matrix output",
            FileKind::MatrixMarket => "a Matrix Market matrix",
            FileKind::BodyJson => "a reduced body (JSON)",
            FileKind::Json => "a JSON file",
            FileKind::Sid => "a reduced body (SID)",
            FileKind::MtxFolder => "a reduced body (Matrix Market folder)",
            FileKind::MbdynFem => {
                "MBDyn's modal FEM file, which flexbody writes for MBDyn but does not read \
                 (inspect the JSON or SID of the same reduction)"
            }
        }
    }

    /// The kind of the file or folder at `path`, if it is recognisable
    /// (`None` also where it cannot be read: its reader says why).
    pub fn of(path: &Path) -> Option<FileKind> {
        if path.is_dir() {
            return path
                .join("index.json")
                .is_file()
                .then_some(FileKind::MtxFolder);
        }
        let head = head(path)?;
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        sniff(&head, &ext)
    }
}

/// The first bytes of the file at `path` as text: enough for its first
/// lines without reading a large file whole.
fn head(path: &Path) -> Option<String> {
    const HEAD: u64 = 8192;
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .ok()?
        .take(HEAD)
        .read_to_end(&mut bytes)
        .ok()?;
    Some(String::from_utf8_lossy(&bytes).into_owned())
}

/// The kind of a file that begins with `head` and has the extension `ext`
/// (lower case, no dot).
fn sniff(head: &str, ext: &str) -> Option<FileKind> {
    let first = head
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#') && !l.starts_with('!'));
    if let Some(line) = first {
        if line.starts_with("**") && head.to_ascii_uppercase().contains("** RECORD GROUP 1") {
            return Some(FileKind::MbdynFem);
        }
        if line.starts_with('*') {
            return Some(FileKind::Deck);
        }
        if line.starts_with("%%MatrixMarket") {
            return Some(FileKind::MatrixMarket);
        }
        if export::sid::looks_like_sid(head) {
            return Some(FileKind::Sid);
        }
        if line.starts_with('{') {
            return Some(if head.contains(export::mtx::INDEX_FORMAT) {
                FileKind::MtxFolder
            } else if head.contains(export::FORMAT) {
                FileKind::BodyJson
            } else {
                FileKind::Json
            });
        }
    }
    let by_extension = match ext {
        "toml" => Some(FileKind::ModelFile),
        "inp" => Some(FileKind::Deck),
        "sti" => Some(FileKind::CalculixMatrices),
        "mtx" => Some(FileKind::MatrixMarket),
        "json" => Some(FileKind::Json),
        "sid" => Some(FileKind::Sid),
        _ => None,
    };
    by_extension.or_else(|| {
        first
            .filter(|l| looks_like_toml(l))
            .map(|_| FileKind::ModelFile)
    })
}

/// A TOML table header (`[study]`) or `key = value` line.
fn looks_like_toml(line: &str) -> bool {
    if line.starts_with('[') {
        return line.ends_with(']');
    }
    line.split_once('=').is_some_and(|(key, _)| {
        let key = key.trim();
        !key.is_empty()
            && key
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "_-.\"' ".contains(c))
    })
}

/// What a command takes: the kinds it reads and how to say so.
#[derive(Clone, Copy, Debug)]
pub struct Takes {
    /// The command's name.
    pub command: &'static str,
    /// The kinds it reads.
    pub kinds: &'static [FileKind],
    /// What it takes, as a phrase following "`command` takes".
    pub what: &'static str,
}

const MODEL_FILE: &[FileKind] = &[FileKind::ModelFile];
const MODEL: &[FileKind] = &[
    FileKind::ModelFile,
    FileKind::Deck,
    FileKind::CalculixMatrices,
    FileKind::MatrixMarket,
];
const MODEL_WHAT: &str = "a model file (.toml), a deck (.inp), CalculiX matrices (job.sti) or Matrix Market stiffness (.mtx) — see docs/model-file.md";

impl Takes {
    /// `study`: a model file with a `[study]` table.
    pub const STUDY: Takes = Takes {
        command: "study",
        kinds: MODEL_FILE,
        what: "a model file (.toml) with a [study] table — see docs/model-file.md",
    };
    /// `simulate`: a model file with a `[simulation]` table.
    pub const SIMULATE: Takes = Takes {
        command: "simulate",
        kinds: MODEL_FILE,
        what: "a model file (.toml) with a [simulation] table — see docs/model-file.md",
    };
    /// `frf`: a model file with an `[frf]` table.
    pub const FRF: Takes = Takes {
        command: "frf",
        kinds: MODEL_FILE,
        what: "a model file (.toml) with an [frf] table — see docs/model-file.md",
    };
    /// `reduce`: a model in any input format.
    pub const REDUCE: Takes = Takes {
        command: "reduce",
        kinds: MODEL,
        what: MODEL_WHAT,
    };
    /// `info`: a model in any input format.
    pub const INFO: Takes = Takes {
        command: "info",
        kinds: MODEL,
        what: MODEL_WHAT,
    };
    /// `modes`: a model in any input format.
    pub const MODES: Takes = Takes {
        command: "modes",
        kinds: MODEL,
        what: MODEL_WHAT,
    };
    /// `inspect`: a reduced body in any of the formats `reduce` writes.
    pub const INSPECT: Takes = Takes {
        command: "inspect",
        kinds: &[
            FileKind::BodyJson,
            FileKind::Json,
            FileKind::Sid,
            FileKind::MtxFolder,
        ],
        what: "a reduced body (JSON, SID or a Matrix Market folder): what `reduce` writes",
    };
    /// `convert`: a reduced body, as `inspect` takes it.
    pub const CONVERT: Takes = Takes {
        command: "convert",
        kinds: Takes::INSPECT.kinds,
        what: Takes::INSPECT.what,
    };

    /// Refuses `path` when it is a recognisable kind of file this command
    /// does not take; anything else passes, for its reader to judge.
    pub fn check(&self, path: &Path) -> Result<(), WrongKind> {
        match FileKind::of(path) {
            Some(kind) if !self.kinds.contains(&kind) => Err(WrongKind {
                path: path.to_path_buf(),
                kind,
                takes: *self,
            }),
            _ => Ok(()),
        }
    }
}

/// A command given a kind of file it does not take.
#[derive(Debug, thiserror::Error)]
#[error("{} is {}; `{}` takes {}", .path.display(), .kind.description(), .takes.command, .takes.what)]
pub struct WrongKind {
    /// The file given.
    pub path: PathBuf,
    /// What it is.
    pub kind: FileKind,
    /// What the command takes.
    pub takes: Takes,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn content_before_extension() {
        assert_eq!(sniff("** comment\n*NODE\n", "toml"), Some(FileKind::Deck));
        assert_eq!(sniff("*HEADING\n", ""), Some(FileKind::Deck));
        assert_eq!(
            sniff("{\n  \"format\": \"flexbody-reduced-body/1\",", "txt"),
            Some(FileKind::BodyJson)
        );
        assert_eq!(sniff("# SID\npart\n", "txt"), Some(FileKind::Sid));
        assert_eq!(sniff("[study]\n", "txt"), Some(FileKind::ModelFile));
        assert_eq!(sniff("title = \"x\"\n", ""), Some(FileKind::ModelFile));
        assert_eq!(sniff("[study\n", "toml"), Some(FileKind::ModelFile));
        assert_eq!(sniff("1 2 3.0\n", "sti"), Some(FileKind::CalculixMatrices));
        assert_eq!(sniff("1 2 3.0\n", "txt"), None);
        assert_eq!(
            sniff("** MBDyn modal file\n** RECORD GROUP 1, HEADER\n", "fem"),
            Some(FileKind::MbdynFem)
        );
    }
}
