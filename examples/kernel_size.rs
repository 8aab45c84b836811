//! The size of each GPU kernel entry point once a driver has inlined every call, for a scene:
//! `cargo run --release --example kernel_size -- SCENE [ENTRY]`.
//!
//! Drivers inline every function at each of its call sites, and lavapipe's compile time grows
//! faster than linearly in the inlined size (its coroutine split walks every basic block for
//! each block). This prints, for the entry (default `gather`) specialised to the scene's
//! constants as a render specialises it, the inlined size (naga statements and expressions) and
//! the functions that contribute most: their own size, how many inlined copies the entry
//! holds, and the product. A function worth shrinking, or calling from fewer places, tops it.

use gpu_photon::integrators::gpu::pipelines::feature_constants;
use gpu_photon::integrators::gpu::shaders::{parse_and_validate, Kernel};
use gpu_photon::integrators::gpu::shape::KernelShape;
use gpu_photon::integrators::gpu::specialise::specialise;
use naga::{Block, Function, Handle, Statement};
use std::collections::HashMap;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        return Err("usage: kernel_size SCENE [ENTRY]".into());
    };
    let entry = args.get(1).map(String::as_str).unwrap_or("gather");
    let scene = gpu_photon::importers::load(std::path::Path::new(path))?;
    let constants = feature_constants(&scene, &KernelShape::DEFAULT, wgpu::DeviceType::Cpu, true);
    let kernel = [Kernel::TracePhotons, Kernel::BuildGrid, Kernel::Gather]
        .into_iter()
        .find(|k| k.entry_points().contains(&entry))
        .ok_or_else(|| format!("no kernel has entry point {entry}"))?;
    let (module, info) = parse_and_validate(&kernel.source()).map_err(|e| e.to_string())?;
    let (module, _) = specialise(&module, &info, entry, &constants)?;
    let ep = module
        .entry_points
        .iter()
        .find(|e| e.name == entry)
        .ok_or("entry point dropped")?;
    let own: HashMap<Handle<Function>, usize> = module
        .functions
        .iter()
        .map(|(h, f)| (h, own_size(f)))
        .collect();
    // Inlined copies of each function: the entry's calls, then each callee's times its own.
    let mut copies: HashMap<Handle<Function>, usize> = HashMap::new();
    let mut pending = vec![(calls(&ep.function.body), 1usize)];
    while let Some((callees, times)) = pending.pop() {
        for f in callees {
            *copies.entry(f).or_default() += times;
            pending.push((calls(&module.functions[f].body), times));
        }
    }
    let total: usize =
        own_size(&ep.function) + copies.iter().map(|(f, n)| own[f] * n).sum::<usize>();
    println!(
        "{entry} of {path}: inlined size {total} ({} functions, entry itself {})",
        copies.len(),
        own_size(&ep.function)
    );
    // A function's size with its callees inlined (one copy of it).
    let mut whole: HashMap<Handle<Function>, usize> = HashMap::new();
    for (h, f) in module.functions.iter() {
        // Callees come before their callers in a validated module.
        let inner: usize = calls(&f.body).iter().map(|c| whole[c]).sum();
        whole.insert(h, own[&h] + inner);
    }
    let mut rows: Vec<_> = copies
        .iter()
        .map(|(f, n)| (own[f] * n, *n, own[f], whole[f], *f))
        .collect();
    rows.sort_by(|a, b| b.cmp(a));
    println!(
        "{:>8} {:>7} {:>6} {:>8}  function",
        "inlined", "copies", "own", "whole"
    );
    for (inlined, n, size, w, f) in rows.into_iter().take(60) {
        let name = module.functions[f].name.as_deref().unwrap_or("?");
        println!("{inlined:>8} {n:>7} {size:>6} {w:>8}  {name}");
    }
    Ok(())
}

/// A function's own size: its expressions and statements, calls counted once each.
fn own_size(f: &Function) -> usize {
    f.expressions.len() + statements(&f.body)
}

fn statements(b: &Block) -> usize {
    b.iter()
        .map(|s| 1 + children(s).into_iter().map(statements).sum::<usize>())
        .sum()
}

/// Every call in `b` (one entry per call site).
fn calls(b: &Block) -> Vec<Handle<Function>> {
    let mut out = Vec::new();
    for s in b.iter() {
        if let Statement::Call { function, .. } = s {
            out.push(*function);
        }
        for c in children(s) {
            out.extend(calls(c));
        }
    }
    out
}

/// The blocks nested in statement `s`.
fn children(s: &Statement) -> Vec<&Block> {
    match s {
        Statement::Block(b) => vec![b],
        Statement::If { accept, reject, .. } => vec![accept, reject],
        Statement::Loop {
            body, continuing, ..
        } => vec![body, continuing],
        Statement::Switch { cases, .. } => cases.iter().map(|c| &c.body).collect(),
        _ => vec![],
    }
}
