//! The text of every built-in table file, embedded (`tableau/catalogue/`),
//! with the lookup of an id and the message for an unknown one. Only data:
//! [`crate::catalogue`] parses an entry, and [`crate::file`] reads a
//! processed method's `kernel = "ID"` from here.

/// One built-in table: its id (the file name without `.toml`) and the file's text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Entry {
    pub id: &'static str,
    pub text: &'static str,
}

/// Every file of `tableau/catalogue/`, in id order, each embedding its
/// text: listed by `build.rs`, so adding a table file is the only edit
/// here. The grouping by kind that `symlab list` shows is the library's list
/// (`integrator_core::for_each_scheme!`), the one place a new table is
/// named.
static ENTRIES: &[Entry] = include!(concat!(env!("OUT_DIR"), "/catalogue_entries.rs"));

/// Every built-in table, in id order.
pub fn entries() -> &'static [Entry] {
    ENTRIES
}

/// The entry with this id, if there is one.
pub fn find(id: &str) -> Option<&'static Entry> {
    ENTRIES.iter().find(|e| e.id == id)
}

/// The ids closest to `id`: those within a small edit distance, or that
/// contain it or are contained in it (so `gauss` finds `gauss1`…`gauss3`),
/// best first, at most five.
pub fn close_matches(id: &str) -> Vec<&'static str> {
    let query = id.trim().to_lowercase();
    if query.is_empty() {
        return Vec::new();
    }
    let allowed = (query.chars().count() / 3).max(2);
    let mut scored: Vec<(usize, &'static str)> = ENTRIES
        .iter()
        .filter_map(|e| {
            let d = edit_distance(&query, e.id);
            let related = e.id.contains(query.as_str()) || query.contains(e.id);
            (d <= allowed || related).then_some((d, e.id))
        })
        .collect();
    scored.sort();
    scored.into_iter().take(5).map(|(_, id)| id).collect()
}

pub(crate) fn unknown_message(id: &str) -> String {
    let close = close_matches(id);
    if close.is_empty() {
        let all: Vec<&str> = ENTRIES.iter().map(|e| e.id).collect();
        format!(
            "no built-in table `{id}`; the catalogue has {}: {}",
            all.len(),
            all.join(", ")
        )
    } else {
        format!(
            "no built-in table `{id}`; did you mean {}?",
            close.join(", ")
        )
    }
}

/// Levenshtein distance over chars.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = Vec::with_capacity(b.len() + 1);
        cur.push(i + 1);
        for (j, cb) in b.iter().enumerate() {
            let substitute = prev[j] + usize::from(ca != *cb);
            cur.push(substitute.min(prev[j + 1] + 1).min(cur[j] + 1));
        }
        prev = cur;
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edit_distances() {
        assert_eq!(edit_distance("gauss2", "gauss2"), 0);
        assert_eq!(edit_distance("gaus2", "gauss2"), 1);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("", "rk4"), 3);
    }

    #[test]
    fn close_matches_rank_the_nearest_first() {
        assert_eq!(close_matches("gaus2").first(), Some(&"gauss2"));
        let gauss = close_matches("gauss");
        for id in ["gauss1", "gauss2", "gauss3"] {
            assert!(gauss.contains(&id), "{gauss:?}");
        }
        assert!(close_matches("yoshida").contains(&"yoshida6"));
        assert!(close_matches("zzzzzzzzzzzz").is_empty());
    }
}
