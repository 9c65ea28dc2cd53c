//! `Retargeter`: a stream of frames through the library's [`vizretarget::Retargeter`], which
//! reuses the mesh from frame to frame as the command line's pipeline does (the same stage
//! calls, so the same frames).
//!
//! The state sits behind a mutex taken with the GIL released: several Python threads may
//! send to one retargeter (their frames are taken in the order they get the lock), and
//! retargeters in different threads run at the same time.

use crate::convert::{input, pack, Out, Packed};
use crate::errors::to_py;
use crate::options::{layer, target, Given, REUSE, STILL};
use crate::stats::frame_stats;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use std::collections::VecDeque;
use std::sync::Mutex;
use vizretarget::{Frame, FrameStats, Options, Status, Target};

struct State {
    target: Target,
    options: Options,
    /// Made on the first frame, whose size a relative target is taken from.
    inner: Option<vizretarget::Retargeter>,
    next_index: u64,
    /// Per frame sent and not yet received: how its result goes back, and the caller's tag.
    pending: VecDeque<(Out, Py<PyAny>)>,
    flushed: bool,
}

#[pyclass(frozen, module = "vizretarget._vizretarget", name = "Retargeter")]
pub struct NativeRetargeter {
    state: Mutex<State>,
}

/// One received frame, packed with the GIL released.
struct Received {
    packed: Packed,
    stats: FrameStats,
    tag: Py<PyAny>,
}

#[pymethods]
impl NativeRetargeter {
    #[new]
    #[pyo3(signature = (size, options=None))]
    fn new(size: &Bound<'_, PyAny>, options: Option<Bound<'_, PyDict>>) -> PyResult<Self> {
        let given = Given::new(options, &[STILL, REUSE])?;
        if given.get::<String>("method")?.is_some_and(|m| m != "mesh") {
            return Err(crate::errors::bad(
                "option method",
                "streams are retargeted with mesh; other methods are for one picture",
            ));
        }
        Ok(NativeRetargeter {
            state: Mutex::new(State {
                target: target(size)?,
                options: crate::options::options(&given)?,
                inner: None,
                next_index: 0,
                pending: VecDeque::new(),
                flushed: false,
            }),
        })
    }

    /// Retargets `frame` (a numpy array or an RGB or RGBA PIL image); `tag` comes back with
    /// its result.
    #[pyo3(signature = (frame, tag, marks=None))]
    fn send(
        &self,
        py: Python<'_>,
        frame: &Bound<'_, PyAny>,
        tag: Py<PyAny>,
        marks: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let p = input(frame, "frame")?;
        let marks = marks.filter(|m| !m.is_none()).map(layer).transpose()?;
        py.detach(|| {
            let mut s = self.lock()?;
            if s.flushed {
                return Err(PyRuntimeError::new_err(
                    "called out of order: send after flush (the stream is over)",
                ));
            }
            if s.inner.is_none() {
                let t = crate::options::resolve(&s.target, p.image.size())?;
                s.inner = Some(vizretarget::Retargeter::new(t, s.options.clone()).map_err(to_py)?);
            }
            let mut f = Frame::new(p.image, s.next_index);
            if let Some(m) = marks {
                f = f.with_marks(m);
            }
            let inner = s
                .inner
                .as_mut()
                .ok_or_else(|| PyRuntimeError::new_err("no stream"))?;
            inner.send_frame(f).map_err(to_py)?;
            s.next_index += 1;
            s.pending.push_back((p.out, tag));
            Ok(())
        })
    }

    /// The next result `(array or Pixels, stats, tag)`, or `None` when none is ready.
    fn receive<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyTuple>>> {
        let got = py.detach(|| -> PyResult<Option<Received>> {
            let mut s = self.lock()?;
            let Some(inner) = s.inner.as_mut() else {
                return Ok(None);
            };
            match inner.receive_frame() {
                Ok(r) => {
                    let (out, tag) = s
                        .pending
                        .pop_front()
                        .ok_or_else(|| PyRuntimeError::new_err("internal error: no tag"))?;
                    Ok(Some(Received {
                        packed: pack(r.image, out),
                        stats: r.stats,
                        tag,
                    }))
                }
                Err(Status::NeedMoreData | Status::Done) => Ok(None),
            }
        })?;
        got.map(|r| {
            PyTuple::new(
                py,
                [
                    r.packed.into_py(py)?,
                    frame_stats(py, &r.stats)?.into_any(),
                    r.tag.into_bound(py),
                ],
            )
        })
        .transpose()
    }

    /// Ends the stream: results still queued stay receivable.
    fn flush(&self, py: Python<'_>) -> PyResult<()> {
        py.detach(|| {
            let mut s = self.lock()?;
            s.flushed = true;
            if let Some(inner) = s.inner.as_mut() {
                inner.flush();
            }
            Ok(())
        })
    }

    /// Frames sent and not yet received.
    fn pending(&self, py: Python<'_>) -> PyResult<usize> {
        py.detach(|| Ok(self.lock()?.pending.len()))
    }
}

impl NativeRetargeter {
    fn lock(&self) -> PyResult<std::sync::MutexGuard<'_, State>> {
        self.state
            .lock()
            .map_err(|_| PyRuntimeError::new_err("the retargeter failed in another thread"))
    }
}
