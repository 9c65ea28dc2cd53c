//! File names of frames, shared between a source that knows them (a folder, a watched
//! directory) and a sink that writes one file per frame.
//!
//! [`crate::Frame`] carries no name: the stages never need one. A source records the name of
//! each frame it reads under its `frame_index`; the sink looks it up when the frame comes out
//! of the pipeline. Only the newest [`FrameNames::WINDOW`] names are kept, far more than a
//! pipeline holds in flight, so an endless watch does not grow memory.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

/// A shared, cheaply cloned map from `frame_index` to the file name the frame came from.
#[derive(Clone, Debug, Default)]
pub struct FrameNames {
    inner: Arc<Mutex<BTreeMap<u64, String>>>,
}

impl FrameNames {
    /// How many of the newest names are kept.
    pub const WINDOW: u64 = 4096;

    pub fn new() -> FrameNames {
        FrameNames::default()
    }

    /// Records that frame `frame_index` was read from the file `path` (its file name).
    pub fn insert_file(&self, frame_index: u64, path: &std::path::Path) {
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        self.insert(frame_index, name.into_owned());
    }

    /// Records that frame `frame_index` came from the file `name`.
    pub fn insert(&self, frame_index: u64, name: impl Into<String>) {
        let mut map = self.lock();
        map.insert(frame_index, name.into());
        if let Some(oldest_kept) = frame_index.checked_sub(Self::WINDOW) {
            // Drop everything older than the window (a few entries at most per call).
            while let Some((&first, _)) = map.first_key_value() {
                if first >= oldest_kept {
                    break;
                }
                map.pop_first();
            }
        }
    }

    /// The name of frame `frame_index`, if a source recorded one.
    pub fn get(&self, frame_index: u64) -> Option<String> {
        self.lock().get(&frame_index).cloned()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, BTreeMap<u64, String>> {
        // A panic elsewhere cannot leave the map half-updated: keep going with its contents.
        self.inner.lock().unwrap_or_else(|e| e.into_inner())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_shared_and_old_ones_dropped() {
        let a = FrameNames::new();
        let b = a.clone();
        a.insert(0, "first.png");
        assert_eq!(b.get(0).as_deref(), Some("first.png"));
        assert_eq!(b.get(1), None);
        for i in 1..=FrameNames::WINDOW + 10 {
            a.insert(i, format!("f{i}"));
        }
        assert_eq!(b.get(0), None);
        assert_eq!(b.get(9), None);
        assert_eq!(b.get(10).as_deref(), Some("f10"));
        assert!(a.lock().len() as u64 <= FrameNames::WINDOW + 1);
    }
}
