//! Line styles: a colour and a dash pattern per curve, distinct within a
//! figure.
//!
//! The colours are the Okabe-Ito set (told apart also with the common
//! colour-vision deficiencies), without its yellow, which is too pale on
//! white, plus three darker ones. A figure with more curves than colours
//! starts the colours again with the next dash pattern, so that no two of
//! its curves look alike up to [`DISTINCT`] curves.

/// The colours, in the order curves receive them.
pub const PALETTE: [&str; 10] = [
    "#0072b2", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9", "#000000", "#8c564b",
    "#7f7f7f", "#9a9a00",
];

/// A dash pattern.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dash {
    Solid,
    Dashed,
    Dotted,
    DashDot,
}

impl Dash {
    /// In the order figures use them.
    pub const ALL: [Dash; 4] = [Dash::Solid, Dash::Dashed, Dash::Dotted, Dash::DashDot];

    /// The SVG `stroke-dasharray` (none for a solid line).
    pub fn dasharray(self) -> Option<&'static str> {
        match self {
            Dash::Solid => None,
            Dash::Dashed => Some("8 4"),
            Dash::Dotted => Some("2 3"),
            Dash::DashDot => Some("8 3 2 3"),
        }
    }
}

/// How many curves of a figure can have styles that differ.
pub const DISTINCT: usize = PALETTE.len() * Dash::ALL.len();

/// The look of a curve (and of its legend swatch).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Style {
    pub color: &'static str,
    pub dash: Dash,
}

impl Style {
    /// The style of the `k`-th curve of a figure: the `k`-th colour, then,
    /// past the last colour, the colours again with the next dash pattern.
    pub fn nth(k: usize) -> Style {
        Style {
            color: PALETTE[k % PALETTE.len()],
            dash: Dash::ALL[(k / PALETTE.len()) % Dash::ALL.len()],
        }
    }

    /// A reference curve: black, solid.
    pub const REFERENCE: Style = Style {
        color: "#000000",
        dash: Dash::Solid,
    };

    /// A curve compared with the reference: vermillion, dashed.
    pub const COMPARED: Style = Style {
        color: "#d55e00",
        dash: Dash::Dashed,
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_distinct_styles_differ_and_the_first_colours_repeat_none() {
        let styles: Vec<Style> = (0..DISTINCT).map(Style::nth).collect();
        for (i, a) in styles.iter().enumerate() {
            assert!(styles[..i].iter().all(|b| b != a), "style {i} repeats");
        }
        let colours: Vec<&str> = (0..PALETTE.len()).map(|k| Style::nth(k).color).collect();
        for (i, c) in colours.iter().enumerate() {
            assert!(!colours[..i].contains(c), "colour {i} repeats");
        }
    }
}
