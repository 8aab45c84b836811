//! The scene's files as Mitsuba 3 reads them (`src/core/parser.cpp`), before any plugin:
//! - `<default name value>` adds a parameter unless one of that name exists (the command
//!   line's `--define`, Mitsuba's `-D`, comes first, so it wins; the first default wins);
//! - `<path value>` (top level only) puts a directory first in the file resolver: relative
//!   to the file it is in, else looked up in the resolver; it must exist;
//! - `<include filename>` is looked up in the resolver (`<path>` directories, the latest
//!   first, then the scene file's directory; not the including file's own directory); its
//!   `<scene>`'s elements (or its root element, when that is not a `<scene>`) are spliced in
//!   its place. At most [`MAX_INCLUDE_DEPTH`] nested includes (Mitsuba's
//!   `MI_XML_INCLUDE_MAX_RECURSION`), [`MAX_INCLUDED_FILES`] and [`MAX_INCLUDED_BYTES`]
//!   in all; a cycle is an error.
//!
//! Attributes are substituted (`$name`) with the parameters known when they are met.

use crate::error::{Error, Result};
use crate::importers::file;
use crate::importers::mitsuba::upgrade::upgrade;
use crate::importers::mitsuba::values::{check_name, resolve, substitute, Params};
use crate::importers::mitsuba::{check_nesting, elements, MAX_DEFAULTS_BYTES};
use roxmltree::{Document, Node};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Most `<include>`s nested in one another (Mitsuba's limit).
pub const MAX_INCLUDE_DEPTH: usize = 15;

/// Most files included in all (a file included twice counts twice).
pub const MAX_INCLUDED_FILES: usize = 1024;

/// Most bytes of the included files together (each read is bounded by its file's size).
pub const MAX_INCLUDED_BYTES: usize = 256 << 20;

/// One file of the scene.
pub(crate) struct Source {
    /// Its name in errors.
    pub name: String,
    /// Its text.
    pub text: String,
}

/// The scene's files and what their `<default>`, `<path>` and `<include>` elements say.
pub(crate) struct Gathered {
    /// The scene file, then every included file in the order met.
    pub sources: Vec<Source>,
    /// (source, byte offset of an `<include>` element) -> the source it includes.
    pub includes: HashMap<(usize, usize), usize>,
    /// The parameters for `$name`.
    pub defaults: Params,
    /// The file resolver: `<path>` directories, the latest first, then the scene's directory.
    pub search: Vec<PathBuf>,
}

/// Parses `text` of the file `name`; errors name its line.
pub(crate) fn parse<'t>(text: &'t str, name: &str) -> Result<Document<'t>> {
    let doc = Document::parse(text).map_err(|e| {
        // A truncated file is reported where it ends (roxmltree says line 1).
        let truncated = matches!(
            e,
            roxmltree::Error::UnexpectedEndOfStream | roxmltree::Error::UnclosedRootNode
        );
        let end = text.trim_end().lines().count().max(1);
        Error::Scene {
            file: name.to_string(),
            line: if truncated { end } else { e.pos().row as usize },
            field: "xml".into(),
            message: e.to_string(),
        }
    })?;
    check_nesting(name, &doc)?;
    Ok(doc)
}

/// Reads the scene `text` (named `file`, in `base_dir`) and every file it includes, with
/// `defines` (NAME, VALUE) as parameters before any `<default>`.
pub(crate) fn gather(
    text: String,
    file: &str,
    base_dir: &Path,
    defines: &[(String, String)],
) -> Result<Gathered> {
    let mut w = Walk {
        g: Gathered {
            sources: vec![Source {
                name: file.to_string(),
                text,
            }],
            includes: HashMap::new(),
            defaults: Params::new(defines),
            search: vec![base_dir.to_path_buf()],
        },
        stack: vec![base_dir.join(file_name(file)).canonicalize().ok()],
        kept: 0,
        read: 0,
    };
    w.walk(0, base_dir, 0)?;
    Ok(w.g)
}

/// The last component of `file` (the scene's name as given).
fn file_name(file: &str) -> &Path {
    Path::new(file)
        .file_name()
        .map_or(Path::new(file), Path::new)
}

/// The walk over the files.
struct Walk {
    g: Gathered,
    /// The files being read, outermost first (canonical paths, for cycles).
    stack: Vec<Option<PathBuf>>,
    /// Bytes of `<default>` values kept.
    kept: usize,
    /// Bytes of the included files read.
    read: usize,
}

/// A located error in the file `name`.
fn err(name: &str, node: Node, field: &str, message: impl Into<String>) -> Error {
    Error::Scene {
        file: name.to_string(),
        line: node.document().text_pos_at(node.range().start).row as usize,
        field: field.to_string(),
        message: message.into(),
    }
}

impl Walk {
    /// The substituted attribute `attr` of `node`, which must be present.
    fn attr(&self, name: &str, node: Node, field: &str, attr: &str) -> Result<String> {
        let tag = node.tag_name().name();
        let Some(raw) = node.attribute(attr) else {
            return Err(err(
                name,
                node,
                field,
                format!("<{tag}> needs a `{attr}` attribute"),
            ));
        };
        substitute(raw, &self.g.defaults).map_err(|m| err(name, node, field, m))
    }

    /// Reads the top-level `<default>`, `<path>` and `<include>` elements of source `idx`
    /// (in directory `dir`, `depth` includes deep), in order, and keeps the source upgraded
    /// when it was written for Mitsuba 0.x (`upgrade.rs`; those elements read the same).
    fn walk(&mut self, idx: usize, dir: &Path, depth: usize) -> Result<()> {
        let name = self.g.sources[idx].name.clone();
        let text = std::mem::take(&mut self.g.sources[idx].text);
        let result = self.walk_text(&text, &name, idx, dir, depth);
        let (text, result) = match result {
            Ok(upgraded) => (upgraded.unwrap_or(text), Ok(())),
            Err(e) => (text, Err(e)),
        };
        self.g.sources[idx].text = text;
        result
    }

    /// [`Self::walk`] over `text`; returns its upgraded text, if it needs one.
    fn walk_text(
        &mut self,
        text: &str,
        name: &str,
        idx: usize,
        dir: &Path,
        depth: usize,
    ) -> Result<Option<String>> {
        let doc = parse(text, name)?;
        let upgraded = upgrade(text, &doc, name)?;
        let root = doc.root_element();
        if root.tag_name().name() != "scene" {
            return Ok(upgraded);
        }
        for node in elements(root) {
            match node.tag_name().name() {
                "default" => {
                    let key = self.attr(name, node, "default", "name")?;
                    check_name(&key).map_err(|m| err(name, node, "default", m))?;
                    let field = format!("default.{key}");
                    let value = self.attr(name, node, &field, "value")?;
                    // Each value is bounded, but many of them (each `$big`) would not be.
                    self.kept += value.len();
                    if self.kept > MAX_DEFAULTS_BYTES {
                        let message =
                            format!("the defaults expand to more than {MAX_DEFAULTS_BYTES} bytes");
                        return Err(err(name, node, &field, message));
                    }
                    self.g.defaults.add(key, value);
                }
                "path" => {
                    let value = self.attr(name, node, "path", "value")?;
                    let mut path = PathBuf::from(&value);
                    if path.is_relative() {
                        path = dir.join(&value);
                        if !path.exists() {
                            path = resolve(&self.g.search, &value);
                        }
                    }
                    if !path.is_dir() {
                        // The value as written: the file and line already say where it is.
                        let message = match PathBuf::from(&value).is_relative() {
                            true => format!(
                                "folder `{value}` not found beside the scene file or in an earlier <path>"
                            ),
                            false => format!("folder `{value}` not found"),
                        };
                        return Err(err(name, node, "path", message));
                    }
                    self.g.search.insert(0, path);
                }
                "include" => self.include(name, node, idx, depth)?,
                _ => {}
            }
        }
        Ok(upgraded)
    }

    /// `<include filename>` in source `idx`: reads the file and walks it.
    fn include(&mut self, name: &str, node: Node, idx: usize, depth: usize) -> Result<()> {
        let field = "include";
        let value = self.attr(name, node, field, "filename")?;
        let path = resolve(&self.g.search, &value);
        if !path.is_file() {
            let dirs: Vec<String> = self
                .g
                .search
                .iter()
                .map(|d| d.display().to_string())
                .collect();
            let message = format!(
                "included file `{value}` not found (searched: {})",
                dirs.join(", ")
            );
            return Err(err(name, node, field, message));
        }
        if depth + 1 > MAX_INCLUDE_DEPTH {
            let message = format!("more than {MAX_INCLUDE_DEPTH} nested <include>s");
            return Err(err(name, node, field, message));
        }
        let canonical = path.canonicalize().ok();
        if canonical.is_some() && self.stack.contains(&canonical) {
            let message = format!("include cycle: `{}` includes itself", path.display());
            return Err(err(name, node, field, message));
        }
        if self.g.sources.len() > MAX_INCLUDED_FILES {
            let message = format!("more than {MAX_INCLUDED_FILES} included files");
            return Err(err(name, node, field, message));
        }
        let text = file::read_text(&path)
            .map_err(|e| err(name, node, field, format!("cannot read it: {e}")))?;
        self.read += text.len();
        if self.read > MAX_INCLUDED_BYTES {
            let message = format!("the included files exceed {MAX_INCLUDED_BYTES} bytes in all");
            return Err(err(name, node, field, message));
        }
        let new = self.g.sources.len();
        self.g.sources.push(Source {
            name: path.display().to_string(),
            text,
        });
        self.g.includes.insert((idx, node.range().start), new);
        self.stack.push(canonical);
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        self.walk(new, &dir, depth + 1)?;
        self.stack.pop();
        Ok(())
    }
}

/// The top-level elements of the scene, `<include>`s replaced by what they include.
pub(crate) fn flatten<'a, 'i>(
    docs: &'a [Document<'i>],
    includes: &HashMap<(usize, usize), usize>,
) -> Vec<Node<'a, 'i>> {
    let mut out = Vec::new();
    splice(docs, includes, 0, &mut out);
    out
}

fn splice<'a, 'i>(
    docs: &'a [Document<'i>],
    includes: &HashMap<(usize, usize), usize>,
    idx: usize,
    out: &mut Vec<Node<'a, 'i>>,
) {
    let root = docs[idx].root_element();
    if idx > 0 && root.tag_name().name() != "scene" {
        out.push(root);
        return;
    }
    for node in elements(root) {
        match includes.get(&(idx, node.range().start)) {
            Some(&j) if node.tag_name().name() == "include" => splice(docs, includes, j, out),
            _ => out.push(node),
        }
    }
}
