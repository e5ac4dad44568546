//! A TOML text and its path: parsing into typed sections, and errors that
//! name the file and the line of a span.

use crate::InputError;
use serde::de::DeserializeOwned;
use std::path::Path;
use toml::Spanned;

/// The text of a TOML file and the path that names it in errors.
#[derive(Clone, Copy, Debug)]
pub struct TomlSource<'a> {
    pub path: &'a Path,
    pub text: &'a str,
}

impl<'a> TomlSource<'a> {
    pub fn new(path: &'a Path, text: &'a str) -> Self {
        Self { path, text }
    }

    /// Deserialises the whole text into `T`; a syntax or type error names
    /// its line, an unknown key or value (serde's `deny_unknown_fields`, an
    /// enum's variants) also its table and the nearest valid spelling. A
    /// number that is not finite (`nan`, `inf`) or beyond
    /// [`LARGEST_NUMBER`](crate::LARGEST_NUMBER) in magnitude is
    /// refused with its line and key, whatever it is read into.
    pub fn parse<T: DeserializeOwned>(&self) -> Result<T, InputError> {
        let value = toml::from_str(self.text).map_err(|e| crate::toml_keys::error(self, &e))?;
        crate::toml_keys::refuse_out_of_range(self)?;
        Ok(value)
    }

    /// Refuses the first top-level key not in `known`, naming its line and
    /// the nearest of `known` (for readers that split the top-level keys
    /// between them, `known` is the union).
    pub fn refuse_unknown_top_level(&self, known: &[&str]) -> Result<(), InputError> {
        crate::toml_keys::refuse_unknown_top_level(self, known)
    }

    /// The 1-based line of a byte offset.
    pub fn line(&self, offset: usize) -> usize {
        self.text[..offset.min(self.text.len())]
            .matches('\n')
            .count()
            + 1
    }

    /// An error at a byte offset (or for the whole file).
    pub fn error(&self, offset: Option<usize>, message: impl Into<String>) -> InputError {
        InputError::Invalid {
            path: self.path.to_path_buf(),
            line: offset.map(|o| self.line(o)),
            message: message.into(),
        }
    }

    /// An error at the start of a spanned value (for the whole file when the
    /// value has no span, as a default has not).
    pub fn at<T>(&self, s: &Spanned<T>, message: impl Into<String>) -> InputError {
        let span = s.span();
        self.error((span.end > 0).then_some(span.start), message)
    }

    /// A path given in the file, relative to the file's folder.
    pub fn relative(&self, file: &str) -> std::path::PathBuf {
        self.path.parent().unwrap_or(Path::new(".")).join(file)
    }
}
