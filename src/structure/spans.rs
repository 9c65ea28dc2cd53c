//! Half-open spans of pixel positions, as the bands and the panels read them.

/// The half-open `spans`, sorted and merged where they touch or overlap.
pub(super) fn merged(spans: impl Iterator<Item = [u32; 2]>) -> Vec<[u32; 2]> {
    let mut spans: Vec<[u32; 2]> = spans.filter(|s| s[0] < s[1]).collect();
    spans.sort_unstable();
    let mut out: Vec<[u32; 2]> = Vec::with_capacity(spans.len());
    for s in spans {
        match out.last_mut() {
            Some(last) if s[0] <= last[1] => last[1] = last[1].max(s[1]),
            _ => out.push(s),
        }
    }
    out
}
