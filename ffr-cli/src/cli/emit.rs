//! `ffr emit --modes`: a body with a fixed mesh and its modal body type.

use super::args::{KernelArgs, ParamArgs};
use ffr::codegen::{generate_kernels, BodySpec, EmitOptions};
use ffr::modal::{ModalSettings, ReducibleBody};
use ffr::runtime::spec::Reference;
use std::path::Path;

/// The file of `--elements n --modes …`: the full body `type_name` (its
/// kernels and parameter struct) and `<type_name>Modal`, the reduction
/// `settings` asks for at the parameter flags' values (checked as `ffr
/// modes` checks them).
pub fn modal_body(
    kernel: &KernelArgs,
    n: usize,
    reference: Reference,
    params: &ParamArgs,
    settings: &ModalSettings,
    type_name: &str,
) -> Result<String, Box<dyn std::error::Error>> {
    let cfg = kernel.config(type_name);
    let model = cfg.model(Path::new("."))?;
    let formalism = model.options.formalism;
    let r = ReducibleBody::from_parts(&kernel.shape, n, reference, formalism, params.values())?;
    let base = r.reduce(Some(settings.modes), &settings.boundary, "--modes")?;
    let modal = ffr::codegen::modal::ModalModel::new(
        &r.spec,
        &r.params,
        &r.invariants,
        base,
        settings,
        model.options.stiffening,
    )?;
    let spec = BodySpec::new(model.shape.clone(), n, reference)?.with_formalism(formalism);
    let set = generate_kernels(&model)?;
    super::check_literals(&set)?;
    Ok(ffr::codegen::emit::emit_modal_body_file(
        &set,
        &spec,
        &EmitOptions {
            type_name: type_name.to_string(),
            ..EmitOptions::default()
        },
        &modal,
        &r.params,
    )?)
}
