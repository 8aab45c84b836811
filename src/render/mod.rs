//! A render around the backends: the session that opens a backend (and `--backend auto`'s
//! rule), the memory budget, progressive passes and their accumulation, adaptive sampling's
//! per-pixel counts, slices and their merge, the report and progress, the signals that end a
//! render early, and images.

pub mod adaptive;
pub mod budget;
pub mod calibration;
pub mod film;
pub mod image_diff;
pub mod memory;
pub mod merge;
pub mod progressive;
pub mod report;
pub mod session;
pub mod slice;
