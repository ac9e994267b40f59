//! The layout of generated kernel functions (SymForce style): the operation
//! count from the program, then `// Inputs`, `// Intermediate terms (N)`,
//! `// Outputs (N)` with the program's counts (`scalar_force_batch`: those of
//! `scalar_force`, per element), and no self-assignment
//! (`let x0 = x0;`) anywhere in an emitted file.

use ffr_codegen::emit::emit_body_file;
use ffr_codegen::{
    emit_kernels_file, generate_kernels, BodySpec, EmitOptions, Formalism, FrameModel, KernelModel,
    KernelOptions, KernelSet, Reference, SceneDim, Shape, Stiffening,
};
use ffr_spec::KernelKind;

fn set(shape: &str, options: KernelOptions) -> KernelSet {
    generate_kernels(&KernelModel::new(
        Shape::resolve(shape, None).unwrap(),
        options,
    ))
    .unwrap()
}

/// Kernel sets across shapes, scenes, formalisms, stiffening models and frames.
fn sets() -> Vec<KernelSet> {
    let o = KernelOptions::new();
    vec![
        set("beam2", o),
        set(
            "beam2",
            o.formalism(Formalism::Lumped)
                .stiffening(Stiffening::FourthOrder)
                .frame(FrameModel::PrescribedAtRest),
        ),
        set(
            "beam2",
            o.scene(SceneDim::Spatial)
                .stiffening(Stiffening::SecondOrder)
                .frame(FrameModel::Prescribed),
        ),
        set("beam3", o.stiffening(Stiffening::SecondOrder)),
    ]
}

/// `let a = a;`: a name bound to itself.
fn self_assignments(text: &str) -> Vec<&str> {
    text.lines()
        .filter(|l| {
            let Some(rest) = l.trim().strip_prefix("let ") else {
                return false;
            };
            let Some((name, value)) = rest.strip_suffix(';').and_then(|r| r.split_once(" = "))
            else {
                return false;
            };
            name.trim() == value.trim()
        })
        .collect()
}

/// Every kernel function of `text`: its name, the operation count above it
/// and the counts of its intermediate and output sections.
fn functions(text: &str) -> Vec<(String, usize, usize, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let count = |l: &str, prefix: &str| -> Option<usize> {
        l.trim()
            .strip_prefix(prefix)?
            .strip_suffix(')')?
            .parse()
            .ok()
    };
    let mut out = Vec::new();
    for (i, l) in lines.iter().enumerate() {
        let Some(ops) = l.trim().strip_prefix("// operations: ") else {
            continue;
        };
        let name = lines[i + 1]
            .trim()
            .strip_prefix("fn ")
            .and_then(|r| r.split('(').next())
            .unwrap_or_else(|| panic!("no function after line {i}: {}", lines[i + 1]));
        let body = &lines[i + 1..];
        let inputs = body.iter().position(|l| l.trim() == "// Inputs").unwrap();
        let (mid, n_mid) = body
            .iter()
            .enumerate()
            .find_map(|(j, l)| count(l, "// Intermediate terms (").map(|n| (j, n)))
            .unwrap();
        let (outs, n_out) = body
            .iter()
            .enumerate()
            .find_map(|(j, l)| count(l, "// Outputs (").map(|n| (j, n)))
            .unwrap();
        assert!(
            inputs < mid && mid < outs,
            "sections of `{name}` out of order"
        );
        // `scalar_force_batch` counts the operations of one element.
        let ops = ops.strip_suffix(" per element").unwrap_or(ops);
        out.push((name.to_string(), ops.parse().unwrap(), n_mid, n_out));
    }
    out
}

#[test]
fn kernel_functions_have_sections_with_the_programs_counts() {
    for set in sets() {
        let text = emit_kernels_file(&set, "K", "::ffr_runtime");
        let fns = functions(&text);
        // Each kernel's function; after `scalar_force`, `scalar_force_batch`
        // with the same program in a loop over the elements.
        let expected: Vec<(&str, KernelKind)> = KernelKind::ALL
            .into_iter()
            .filter(|k| set.program(*k).is_some())
            .flat_map(|k| {
                let batch = (k == KernelKind::ScalarForce).then_some(("scalar_force_batch", k));
                std::iter::once((k.name(), k)).chain(batch)
            })
            .collect();
        assert_eq!(
            fns.iter().map(|f| f.0.as_str()).collect::<Vec<_>>(),
            expected.iter().map(|k| k.0).collect::<Vec<_>>()
        );
        for ((name, ops, n_mid, n_out), (_, kind)) in fns.iter().zip(expected) {
            let p = set.program(kind).unwrap();
            assert_eq!(*ops, p.ops(), "{name}");
            assert_eq!(*n_mid, p.stmts.len(), "{name}");
            assert_eq!(*n_out, p.outputs.len(), "{name}");
        }
        assert!(
            !text.contains("/// operations"),
            "an operation count as a doc comment"
        );
    }
}

#[test]
fn no_self_assignments_in_emitted_files() {
    for set in sets() {
        let text = emit_kernels_file(&set, "K", "::ffr_runtime");
        assert_eq!(self_assignments(&text), Vec::<&str>::new());
        let spec = BodySpec::new(set.model().shape.clone(), 3, Reference::Pinned)
            .unwrap()
            .with_formalism(set.model().options.formalism);
        let body = emit_body_file(&set, &spec, &EmitOptions::default());
        assert_eq!(self_assignments(&body), Vec::<&str>::new());
    }
    // The check itself finds one.
    assert_eq!(
        self_assignments("    let x0 = x0;\n    let x1 = x0;\n"),
        ["    let x0 = x0;"]
    );
}
