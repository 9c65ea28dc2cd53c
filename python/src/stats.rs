//! A frame's statistics as a dict, with the names `--stats-json` gives them.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use vizretarget::{Decision, FrameStats};

pub fn frame_stats<'py>(py: Python<'py>, s: &FrameStats) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("frame_index", s.frame_index)?;
    d.set_item(
        "decision",
        match s.decision {
            Decision::Rebuild => "rebuild",
            Decision::Update => "update",
            Decision::Reuse => "reuse",
        },
    )?;
    d.set_item("vertices", s.vertices)?;
    d.set_item("triangles", s.triangles)?;
    d.set_item("dof", s.dof)?;
    d.set_item("updated_tiles", s.updated_tiles)?;
    d.set_item("data_areas", s.data_areas)?;
    d.set_item("floated", s.floated)?;
    d.set_item("dropped", s.dropped)?;
    d.set_item("panels", s.panels)?;
    d.set_item("fitted", s.fitted.map(|[x0, y0, x1, y1]| (x0, y0, x1, y1)))?;
    let t = &s.times;
    let ms = PyDict::new(py);
    ms.set_item("vsm", t.vsm_ms)?;
    ms.set_item("mesh", t.mesh_ms)?;
    ms.set_item("solve", t.solve_ms)?;
    ms.set_item("render", t.render_ms)?;
    ms.set_item("total", t.total_ms())?;
    d.set_item("ms", ms)?;
    Ok(d)
}
