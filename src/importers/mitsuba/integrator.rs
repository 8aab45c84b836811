//! Mitsuba's `<integrator>`: a hint, never a technique (any type renders with our photon
//! mapping), read for the path lengths it allows.
//!
//! Mitsuba nests integrators: `moment` and `aov` wrap the one that renders (its `max_depth`
//! is inside), so the whole nest is read. `max_depth` M counts path segments (-1: unbounded);
//! the `direct` integrator renders what `path` with M = 2 does (emitters seen directly and
//! light after one bounce). M caps our photon paths at M - 1 bounces and sets camera paths'
//! length to M - 1 (`max_depth`, whatever our own default; -1, unbounded, is [`MAX_BOUNCES`]: the rough
//! glass sphere of `scenes/mitsuba/materials.xml` at M = 64 was 4% dark on its rim with our
//! default 12): a hit after M - 1 bounces only emits, one before it also
//! takes direct light and photon estimates (M = 2: a mirror shows the emitters it reflects,
//! not the light on what it reflects). A short M (at most [`DIRECT_MODE_MAX_DEPTH`]) also makes
//! `direct` the render mode: its shadow rays carry the direct light and the global map only
//! photons of depth 1 to M - 2, so a camera path whose first diffuse hit ends it is capped
//! exactly, where final gathering would add one bounce past M (measured on Mitsuba's suite:
//! its sphere grids at M = 2 were 1-8% bright, the rough dielectric's 2x; in the direct mode
//! all are within 3%, most within 1.5%). A longer M keeps the file's mode (our own scenes at
//! max_depth 64 still render with final gathering): the bounce past M is a small share there.
//! `rr_depth` changes only noise (our photons' Russian roulette works by reflectance from the
//! first bounce): read and named.

use crate::error::Result;
use crate::importers::mitsuba::Importer;
use crate::settings::{Mode, MAX_BOUNCES};
use roxmltree::Node;

/// Deepest nest of integrators read (Mitsuba's wrappers nest one or two).
const MAX_NEST: usize = 8;

/// The longest `max_depth` that selects the direct render mode (see the module's docs).
pub(crate) const DIRECT_MODE_MAX_DEPTH: u32 = 4;

/// What a nest of integrators asks for.
#[derive(Default)]
struct Nest {
    /// The types, outermost first.
    kinds: Vec<String>,
    /// The smallest `max_depth` M of the nest (a `direct` integrator's is 2).
    max_depth: Option<u32>,
    notes: Vec<String>,
}

impl Importer<'_> {
    /// `<integrator>` of any type, with the integrators nested in it: one warning saying that
    /// our technique renders it; `max_depth` (or a `direct` integrator) caps path lengths.
    pub(crate) fn integrator(&mut self, node: Node, field: &str) -> Result<()> {
        let mut nest = Nest::default();
        self.read_integrator(node, field, 0, &mut nest)?;
        if let Some(m) = nest.max_depth {
            let s = self.b.settings();
            s.max_photon_bounces = s.max_photon_bounces.min((m - 1).max(1));
            s.max_depth = (m.max(2) - 1).clamp(1, MAX_BOUNCES);
            if m == 1 {
                nest.notes
                    .push("max_depth 1 (emitters only) rendered as 2".to_string());
            }
            if m <= DIRECT_MODE_MAX_DEPTH {
                s.mode = Mode::Direct;
                nest.notes.push(format!(
                    "paths capped at {} segments: mode `direct`",
                    m.max(2)
                ));
            }
        }
        let notes = match nest.notes.is_empty() {
            true => String::new(),
            false => format!("; {}", nest.notes.join(", ")),
        };
        self.warnings.push(format!(
            "{}: {field}: integrator `{}` rendered with our photon mapping (the render \
             mode: [render] mode, --mode){notes}",
            self.cx.loc(node),
            // Innermost first: "`path` in `moment`".
            nest.kinds
                .iter()
                .rev()
                .cloned()
                .collect::<Vec<_>>()
                .join("` in `")
        ));
        Ok(())
    }

    /// Reads `node` (an integrator at nesting `level`) and the integrators inside it.
    fn read_integrator(
        &self,
        node: Node,
        field: &str,
        level: usize,
        nest: &mut Nest,
    ) -> Result<()> {
        if level >= MAX_NEST {
            let message = format!("more than {MAX_NEST} nested integrators");
            return Err(self.cx.err(node, field, message));
        }
        let kind = self.cx.attr(node, field, "type")?.unwrap_or_default();
        if kind == "direct" {
            nest.max_depth = Some(nest.max_depth.map_or(2, |m| m.min(2)));
        }
        nest.kinds.push(kind);
        for child in node.children().filter(Node::is_element) {
            let name = child.attribute("name").unwrap_or_default();
            if child.tag_name().name() == "integrator" {
                let at = format!("{field}.integrator");
                self.read_integrator(child, &at, level + 1, nest)?;
                continue;
            }
            if !matches!(name, "max_depth" | "rr_depth") {
                continue;
            }
            let at = format!("{field}.{name}");
            let text = self.cx.need_attr(child, &at, "value")?;
            let depth = match text.trim().parse::<i64>() {
                Ok(v) if v == -1 || (v >= 1 && v <= i64::from(u32::MAX)) => v,
                _ => {
                    let message = format!("must be -1 or a positive integer (got `{text}`)");
                    return Err(self.cx.err(child, &at, message));
                }
            };
            if name == "rr_depth" {
                nest.notes
                    .push(format!("rr_depth {depth} changes only noise, not used"));
            } else {
                // -1 (unbounded): our longest paths.
                let m = match depth {
                    -1 => MAX_BOUNCES + 1,
                    d => d.min(i64::from(MAX_BOUNCES) + 2) as u32,
                };
                nest.max_depth = Some(nest.max_depth.map_or(m, |d| d.min(m)));
            }
        }
        Ok(())
    }
}
