//! The nearest of a set of known words to a misspelt one, for errors that
//! refuse an unknown deck keyword, TOML key or TOML value with a "did you
//! mean".

/// The candidate nearest to `word` when it is close enough to be a
/// misspelling: at most 1 edit (insertion, deletion, substitution,
/// transposition of neighbours) for words of up to 4 characters, 2 for longer ones. Spaces
/// in a candidate are ignored when comparing (deck keywords are matched
/// without them); the candidate is returned as given. Of equally near
/// candidates the first wins.
pub fn nearest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let limit = if word.chars().count() <= 4 { 1 } else { 2 };
    candidates
        .into_iter()
        .map(|k| (edit_distance(word, &k.replace(' ', "")), k))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k)
}

/// Edit distance counting insertions, deletions, substitutions and
/// transpositions of neighbours (`lwa` is 1 from `law`), each once
/// (optimal string alignment).
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    // d[i][j]: distance between the first i of a and the first j of b.
    let mut d = vec![vec![0; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    d[0] = (0..=b.len()).collect();
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let substitute = d[i - 1][j - 1] + usize::from(a[i - 1] != b[j - 1]);
            let mut best = substitute.min(d[i - 1][j] + 1).min(d[i][j - 1] + 1);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                best = best.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = best;
        }
    }
    d[a.len()][b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances() {
        assert_eq!(edit_distance("BOUNDRY", "BOUNDARY"), 1);
        assert_eq!(edit_distance("ELASTC", "ELASTIC"), 1);
        assert_eq!(edit_distance("NODE", "NSET"), 3);
        assert_eq!(edit_distance("", "ABC"), 3);
        assert_eq!(edit_distance("shear_aera_y", "shear_area_y"), 1);
        assert_eq!(edit_distance("lwa", "law"), 1);
        assert_eq!(edit_distance("centre", "center"), 1);
        assert_eq!(edit_distance("ab", "ba"), 1);
        assert_eq!(edit_distance("abc", "ca"), 3);
    }

    #[test]
    fn nearest_keywords_and_keys() {
        let known = ["BOUNDARY", "SOLID SECTION", "NODE", "NSET"];
        assert_eq!(nearest("BOUNDRY", known), Some("BOUNDARY"));
        assert_eq!(nearest("SOLIDSECTON", known), Some("SOLID SECTION"));
        assert_eq!(nearest("NOD", known), Some("NODE"));
        assert_eq!(nearest("FOOBAR", known), None);
        // Short words take one edit only.
        assert_eq!(nearest("NSAT", ["NODE"]), None);
        let keys = ["shear_area_y", "shear_area_z", "area"];
        assert_eq!(nearest("shear_area_yy", keys), Some("shear_area_y"));
        assert_eq!(nearest("uzz", ["ux", "uy", "uz"]), Some("uz"));
        assert_eq!(nearest("rigd", ["rigid", "distributing"]), Some("rigid"));
    }
}
