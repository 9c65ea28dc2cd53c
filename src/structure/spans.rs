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

/// The half-open runs of `lo..hi` where `ok` holds (a band's clean rows, a gutter's).
pub(super) fn runs_where(lo: u32, hi: u32, ok: impl Fn(u32) -> bool) -> Vec<[u32; 2]> {
    let mut out = Vec::new();
    let mut start = None;
    for p in lo..hi {
        match (ok(p), start) {
            (true, None) => start = Some(p),
            (false, Some(s)) => {
                out.push([s, p]);
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push([s, hi]);
    }
    out
}
