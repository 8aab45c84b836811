//! One entry point of a kernel family specialised to a render's override constants before the
//! driver sees it: the constants substituted, every branch they decide removed, and whatever
//! only the removed branches and the other entry points reached dropped.
//!
//! Drivers inline every call before they fold constants, so a feature a scene lacks still
//! cost its whole call tree in each inlined copy (lavapipe: the gather pipeline of a diffuse
//! Cornell box spent half its creation time on texture code no branch could reach). naga
//! substitutes the constants (`process_overrides`) but keeps the dead branches; this pass
//! removes them in naga's IR.

use naga::back::pipeline_constants::process_overrides;
use naga::back::PipelineConstants;
use naga::compact::{compact, KeepUnused};
use naga::{
    BinaryOperator, Block, Expression, Function, Handle, Literal, LocalVariable, Module, Statement,
    SwitchCase, UnaryOperator,
};
use std::collections::HashMap;

/// Override constants by name, as a pipeline takes them.
pub type Constants<'c> = Vec<(&'c str, f64)>;

/// `module` (validated, with `info`) reduced to the compute entry point `entry` with the
/// override constants `constants` substituted and the branches they decide removed, and the
/// constants the pipeline must still pass (overrides sizing workgroup arrays stay
/// overrides); or why naga could not make it.
pub fn specialise<'c>(
    module: &Module,
    info: &naga::valid::ModuleInfo,
    entry: &str,
    constants: &[(&'c str, f64)],
) -> Result<(Module, Constants<'c>), String> {
    // Constants only other entry points declare are not an error here.
    let values: PipelineConstants = constants
        .iter()
        .filter(|(name, _)| declares(module, name))
        .map(|&(name, value)| (name.to_string(), value))
        .collect();
    let (substituted, _) = process_overrides(
        module,
        info,
        Some((naga::ShaderStage::Compute, entry)),
        &values,
    )
    .map_err(|e| e.to_string())?;
    let mut module = substituted.into_owned();
    let decided = Decided::of(&module);
    for (_, f) in module.functions.iter_mut() {
        prune_function(f, &decided);
    }
    for e in module.entry_points.iter_mut() {
        prune_function(&mut e.function, &decided);
    }
    compact(&mut module, KeepUnused::No);
    let kept = constants
        .iter()
        .filter(|(name, _)| declares(&module, name))
        .copied()
        .collect();
    Ok((module, kept))
}

/// Whether `module` declares the override constant `name`.
fn declares(module: &Module, name: &str) -> bool {
    module
        .overrides
        .iter()
        .any(|(_, o)| o.name.as_deref() == Some(name))
}

/// The boolean value of each module-scope constant that has one.
struct Decided {
    bools: Vec<Option<bool>>,
}

/// Boolean locals whose value is known at a point of a function's body: the naga front end
/// lowers `a && b` and `a || b` to a local stored in an `if` and loaded by the condition.
type Known = HashMap<Handle<LocalVariable>, bool>;

impl Decided {
    fn of(module: &Module) -> Self {
        let bools = module
            .constants
            .iter()
            .map(|(_, c)| match module.global_expressions[c.init] {
                Expression::Literal(Literal::Bool(b)) => Some(b),
                _ => None,
            })
            .collect();
        Decided { bools }
    }

    /// The value of boolean expression `h` of `f` when constants decide it.
    fn value(&self, f: &Function, h: Handle<Expression>, known: &Known) -> Option<bool> {
        match f.expressions[h] {
            Expression::Literal(Literal::Bool(b)) => Some(b),
            Expression::Constant(c) => self.bools.get(c.index()).copied().flatten(),
            Expression::Load { pointer } => match f.expressions[pointer] {
                Expression::LocalVariable(l) => known.get(&l).copied(),
                _ => None,
            },
            Expression::Unary {
                op: UnaryOperator::LogicalNot,
                expr,
            } => self.value(f, expr, known).map(|b| !b),
            Expression::Binary { op, left, right } => {
                let (l, r) = (self.value(f, left, known), self.value(f, right, known));
                match op {
                    BinaryOperator::LogicalAnd => match (l, r) {
                        (Some(false), _) | (_, Some(false)) => Some(false),
                        (Some(true), Some(true)) => Some(true),
                        _ => None,
                    },
                    BinaryOperator::LogicalOr => match (l, r) {
                        (Some(true), _) | (_, Some(true)) => Some(true),
                        (Some(false), Some(false)) => Some(false),
                        _ => None,
                    },
                    _ => None,
                }
            }
            _ => None,
        }
    }
}

fn prune_function(f: &mut Function, decided: &Decided) {
    let body = std::mem::take(&mut f.body);
    let mut known = Known::new();
    for (l, local) in f.local_variables.iter() {
        if let Some(init) = local.init {
            if let Some(b) = decided.value(f, init, &known) {
                known.insert(l, b);
            }
        }
    }
    f.body = prune_block(body, f, decided, &mut known);
    // `compact` keeps every named expression alive, and one of a removed branch may name a
    // call's result whose function goes; names only label the driver's code.
    f.named_expressions.clear();
}

/// The local variable pointer `h` of `f` points into, if any.
fn local_root(f: &Function, mut h: Handle<Expression>) -> Option<Handle<LocalVariable>> {
    loop {
        match f.expressions[h] {
            Expression::LocalVariable(l) => return Some(l),
            Expression::Access { base, .. } | Expression::AccessIndex { base, .. } => h = base,
            _ => return None,
        }
    }
}

/// Forgets every local `block` may write (stores, pointers passed to calls).
fn forget_written(block: &Block, f: &Function, known: &mut Known) {
    for statement in block.iter() {
        match statement {
            Statement::Store { pointer, .. } => {
                if let Some(l) = local_root(f, *pointer) {
                    known.remove(&l);
                }
            }
            Statement::Call { arguments, .. } => {
                for &a in arguments {
                    if let Some(l) = local_root(f, a) {
                        known.remove(&l);
                    }
                }
            }
            Statement::Block(b) => forget_written(b, f, known),
            Statement::If { accept, reject, .. } => {
                forget_written(accept, f, known);
                forget_written(reject, f, known);
            }
            Statement::Switch { cases, .. } => {
                for c in cases {
                    forget_written(&c.body, f, known);
                }
            }
            Statement::Loop {
                body, continuing, ..
            } => {
                forget_written(body, f, known);
                forget_written(continuing, f, known);
            }
            _ => {}
        }
    }
}

/// `block` with every `if` whose condition the constants decide replaced by the branch
/// taken; `known` holds the boolean locals known on entry and on return at its end.
fn prune_block(block: Block, f: &Function, decided: &Decided, known: &mut Known) -> Block {
    let mut out = Block::with_capacity(block.len());
    for (statement, span) in block.span_into_iter() {
        let statement = match statement {
            Statement::If {
                condition,
                accept,
                reject,
            } => match decided.value(f, condition, known) {
                Some(true) => Statement::Block(prune_block(accept, f, decided, known)),
                Some(false) => Statement::Block(prune_block(reject, f, decided, known)),
                None => {
                    let mut after_accept = known.clone();
                    let accept = prune_block(accept, f, decided, &mut after_accept);
                    let reject = prune_block(reject, f, decided, known);
                    known.retain(|l, b| after_accept.get(l) == Some(b));
                    Statement::If {
                        condition,
                        accept,
                        reject,
                    }
                }
            },
            Statement::Block(b) => Statement::Block(prune_block(b, f, decided, known)),
            Statement::Switch { selector, cases } => {
                for c in &cases {
                    forget_written(&c.body, f, known);
                }
                let cases = cases
                    .into_iter()
                    .map(|c| SwitchCase {
                        body: prune_block(c.body, f, decided, &mut known.clone()),
                        ..c
                    })
                    .collect();
                Statement::Switch { selector, cases }
            }
            Statement::Loop {
                body,
                continuing,
                break_if,
            } => {
                forget_written(&body, f, known);
                forget_written(&continuing, f, known);
                Statement::Loop {
                    body: prune_block(body, f, decided, &mut known.clone()),
                    continuing: prune_block(continuing, f, decided, &mut known.clone()),
                    break_if,
                }
            }
            Statement::Store { pointer, value } => {
                if let Some(l) = local_root(f, pointer) {
                    match (&f.expressions[pointer], decided.value(f, value, known)) {
                        (Expression::LocalVariable(_), Some(b)) => known.insert(l, b),
                        _ => known.remove(&l),
                    };
                }
                Statement::Store { pointer, value }
            }
            Statement::Call {
                function,
                arguments,
                result,
            } => {
                for &a in &arguments {
                    if let Some(l) = local_root(f, a) {
                        known.remove(&l);
                    }
                }
                Statement::Call {
                    function,
                    arguments,
                    result,
                }
            }
            other => other,
        };
        let exits = exits(&statement);
        out.push(statement, span);
        if exits {
            // What follows in this block never runs (naga keeps it; drivers inline it).
            break;
        }
    }
    out
}

/// Whether control never passes `statement` to the statement after it.
fn exits(statement: &Statement) -> bool {
    match statement {
        Statement::Return { .. } | Statement::Kill | Statement::Break | Statement::Continue => true,
        Statement::Block(b) => b.last().is_some_and(exits),
        Statement::If { accept, reject, .. } => {
            accept.last().is_some_and(exits) && reject.last().is_some_and(exits)
        }
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::gpu::shaders::{parse_and_validate, Kernel};

    fn validated(source: &str) -> (Module, naga::valid::ModuleInfo) {
        parse_and_validate(source).unwrap()
    }

    fn has_function(m: &Module, name: &str) -> bool {
        m.functions
            .iter()
            .any(|(_, f)| f.name.as_deref() == Some(name))
    }

    /// Every entry point of every family specialises, with the defaults and with every
    /// feature off, to a module that validates, has no overrides left and one entry point.
    #[test]
    fn every_entry_point_specialises_to_a_valid_module() {
        for kernel in Kernel::ALL {
            let source = kernel.source();
            let (module, info) = validated(&source);
            let off: Vec<(&str, f64)> = module
                .overrides
                .iter()
                .filter_map(|(_, o)| o.name.as_deref())
                .filter(|n| n.starts_with("HAS_"))
                .map(|n| (n, 0.0))
                .collect();
            for constants in [&[][..], &off[..]] {
                for entry in kernel.entry_points() {
                    let (m, _) = specialise(&module, &info, entry, constants)
                        .unwrap_or_else(|e| panic!("{}: {entry}: {e}", kernel.name()));
                    naga::valid::Validator::new(
                        naga::valid::ValidationFlags::all(),
                        naga::valid::Capabilities::all(),
                    )
                    .validate(&m)
                    .unwrap_or_else(|e| panic!("{}: {entry}: {e:?}", kernel.name()));
                    let left: Vec<_> = m
                        .overrides
                        .iter()
                        .filter_map(|(_, o)| o.name.clone())
                        .collect();
                    assert!(
                        left.iter().all(|n| !n.starts_with("HAS_")),
                        "{entry}: features left undecided: {left:?}"
                    );
                    assert_eq!(m.entry_points.len(), 1, "{entry}");
                    assert_eq!(m.entry_points[0].name, *entry);
                }
            }
        }
    }

    /// A feature switched off takes its code with it; switched on, it stays.
    #[test]
    fn a_feature_switched_off_leaves_no_code() {
        let (module, info) = validated(&Kernel::Gather.source());
        let with = specialise(&module, &info, "gather", &[("HAS_TEXTURES", 1.0)])
            .unwrap()
            .0;
        let without = specialise(&module, &info, "gather", &[("HAS_TEXTURES", 0.0)])
            .unwrap()
            .0;
        assert!(has_function(&with, "texture_eval_rgba"));
        assert!(!has_function(&without, "texture_eval_rgba"));
        assert!(without.functions.len() < with.functions.len());
    }

    /// A condition constants do not decide stays a branch.
    #[test]
    fn undecided_conditions_stay() {
        let source = "override F: bool = true;\n\
            @group(0) @binding(0) var<storage, read_write> out: array<u32>;\n\
            fn one() -> u32 { return 1u; }\n\
            fn two() -> u32 { return 2u; }\n\
            @compute @workgroup_size(1) fn main() {\n\
                if F && out[0] == 0u { out[1] = one(); }\n\
                if !F { out[2] = two(); }\n\
                if F || out[0] == 0u { out[3] = 3u; }\n\
            }";
        let (module, info) = validated(source);
        let on = specialise(&module, &info, "main", &[("F", 1.0)]).unwrap().0;
        assert!(has_function(&on, "one") && !has_function(&on, "two"));
        let ifs = |m: &Module| {
            m.entry_points[0]
                .function
                .body
                .iter()
                .filter(|s| matches!(s, Statement::If { .. }))
                .count()
        };
        assert_eq!(ifs(&on), 1, "only the runtime-dependent branch is left");
        let off = specialise(&module, &info, "main", &[("F", 0.0)]).unwrap().0;
        assert!(!has_function(&off, "one") && has_function(&off, "two"));
        assert_eq!(ifs(&off), 1);
    }

    /// Code after a return the constants decide is dropped with what only it calls.
    #[test]
    fn code_after_a_decided_return_goes() {
        let source = "override F: bool = true;\n\
            @group(0) @binding(0) var<storage, read_write> out: array<u32>;\n\
            fn three() -> u32 { return 3u; }\n\
            fn early() -> u32 {\n\
                if !F || out[0] == 7u { return 0u; }\n\
                return three();\n\
            }\n\
            @compute @workgroup_size(1) fn main() { out[1] = early(); }";
        let (module, info) = validated(source);
        let off = specialise(&module, &info, "main", &[("F", 0.0)]).unwrap().0;
        assert!(has_function(&off, "early") && !has_function(&off, "three"));
        let on = specialise(&module, &info, "main", &[("F", 1.0)]).unwrap().0;
        assert!(has_function(&on, "three"));
    }
}
