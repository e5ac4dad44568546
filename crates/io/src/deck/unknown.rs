//! Keywords the reader does not know. A keyword that is neither read,
//! deliberately ignored nor refused may change K, M or D, so by default
//! the deck is refused at its first unknown keyword, with the nearest
//! known keyword when one is close (a misspelling such as `*BOUNDRY`).
//! With [`DeckOptions::allow_unknown`] they are skipped and collected into
//! [`UnknownKeywords`], which the caller shows as one warning.

use std::path::PathBuf;

/// How a deck is read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DeckOptions {
    /// Skip unknown keywords (collected in [`Deck::unknown`](super::Deck))
    /// instead of refusing the deck.
    pub allow_unknown: bool,
    /// The memory the reading may take (the command line's
    /// `--max-memory`): set entries, `GENERATE` ranges and the elements of
    /// a model file's `[[beam_line]]`s are compared with it before they
    /// are stored.
    pub memory: flexbody_linalg::memory::Budget,
}

/// An unknown keyword skipped under [`DeckOptions::allow_unknown`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownKeyword {
    /// As written, upper case with single spaces: `"*BOUNDRY"`.
    pub keyword: String,
    /// Where it is, in order: `"line 12"`, `"nodes.inp line 4"`.
    pub lines: Vec<String>,
}

/// The unknown keywords skipped in one deck, each once, in order of first
/// use.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct UnknownKeywords {
    /// The deck (its main file).
    pub deck: PathBuf,
    pub keywords: Vec<UnknownKeyword>,
}

impl UnknownKeywords {
    /// Records `keyword` at `line`.
    pub(super) fn add(&mut self, keyword: &str, line: String) {
        match self.keywords.iter_mut().find(|k| k.keyword == keyword) {
            Some(k) => k.lines.push(line),
            None => self.keywords.push(UnknownKeyword {
                keyword: keyword.to_string(),
                lines: vec![line],
            }),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.keywords.is_empty()
    }

    /// The one warning that lists them, `None` when there are none:
    /// `deck.inp: unknown keywords skipped (--allow-unknown; ...): *BOUNDRY
    /// (line 12), *FOO (lines 3, 9)`.
    pub fn summary(&self) -> Option<String> {
        if self.is_empty() {
            return None;
        }
        let list: Vec<String> = self
            .keywords
            .iter()
            .map(|k| {
                let lines = k
                    .lines
                    .iter()
                    .map(|l| l.strip_prefix("line ").unwrap_or(l))
                    .collect::<Vec<_>>()
                    .join(", ");
                let word = if k.lines.len() == 1 { "line" } else { "lines" };
                // Lines of included files keep their file name.
                if k.lines.iter().all(|l| l.starts_with("line ")) {
                    format!("{} ({word} {lines})", k.keyword)
                } else {
                    format!("{} ({})", k.keyword, k.lines.join(", "))
                }
            })
            .collect();
        Some(format!(
            "{}: unknown keywords skipped (--allow-unknown; they may have changed K, M or D): {}",
            self.deck.display(),
            list.join(", ")
        ))
    }
}
