//! A modal body's generated inertia kernels run from tapes at run time
//! ([`TapeModalKernels`]): the programs `ffr emit --modes` compiles
//! (`ffr_codegen::modal::generate_modal_kernels`), interpreted in exactly
//! their operation order, for a modal body reduced at run time (`ffr
//! spin-up --modes K --tape`). Feature `tape`.

use crate::{KernelInput, MassOut, ModalKernels, ResidualOut, TangentOut};
use ffr_codegen::eom::OutArr;
use ffr_codegen::modal::ModalKernelSet;
use ffr_codegen::program::{Inputs, Tape};

/// [`ModalKernels`] evaluated from the generator's programs.
#[derive(Debug)]
pub struct TapeModalKernels {
    modes: usize,
    scene_dim: usize,
    linear_elastic: bool,
    /// `mass`, `residual`, `tangent`, `residual_elastic`, `tangent_elastic`.
    tapes: [Tape; 5],
    scratch: usize,
}

impl TapeModalKernels {
    /// Tapes of generated modal programs.
    pub fn from_set(set: &ModalKernelSet) -> Self {
        let tapes = set.programs().map(|(_, p)| p.tape());
        let scratch = tapes.iter().map(Tape::n_slots).max().unwrap_or(0);
        Self {
            modes: set.modes,
            scene_dim: set.scene.dim(),
            linear_elastic: set.linear_elastic,
            tapes,
            scratch,
        }
    }
}

/// Runs `t` on `inputs` in `scratch` (at least [`ModalKernels::scratch`]
/// long, as the caller's work gives) and hands each output to `out`.
fn run(t: &Tape, inputs: &Inputs, scratch: &mut [f64], mut out: impl FnMut(OutArr, usize, f64)) {
    let Some(slots) = scratch.get_mut(..t.n_slots()) else {
        return;
    };
    t.run(inputs, slots);
    for &((arr, i), r) in &t.outputs {
        out(arr, i as usize, slots[r as usize]);
    }
}

fn inputs<'a>(x: &KernelInput<'a>, bp: f64, gp: f64) -> Inputs<'a> {
    Inputs {
        frame: x.frame,
        q: x.q,
        qd: x.qd,
        qdd: x.qdd,
        bp,
        gp,
        ..Inputs::default()
    }
}

impl ModalKernels for TapeModalKernels {
    fn modes(&self) -> usize {
        self.modes
    }

    fn scene_dim(&self) -> usize {
        self.scene_dim
    }

    fn linear_elastic(&self) -> bool {
        self.linear_elastic
    }

    fn scratch(&self) -> usize {
        self.scratch
    }

    fn mass(&self, q: &[f64], out: &mut MassOut, scratch: &mut [f64]) {
        let x = Inputs {
            q,
            ..Inputs::default()
        };
        run(&self.tapes[0], &x, scratch, |arr, i, v| match arr {
            OutArr::St => out.s_t[i] = v,
            OutArr::Mee => out.m_ee[i] = v,
            OutArr::MeFrame => out.m_e_frame[i] = v,
            OutArr::MrefE => out.m_ref_e[i] = v,
            OutArr::MrefFrame => out.m_ref_frame[i] = v,
            _ => {}
        });
    }

    fn residual(&self, x: &KernelInput, out: &mut ResidualOut, scratch: &mut [f64]) {
        run(
            &self.tapes[1],
            &inputs(x, 0.0, 0.0),
            scratch,
            |arr, i, v| match arr {
                OutArr::Fr => out.f_r[i] = v,
                OutArr::Fth => out.f_th[i] = v,
                OutArr::Fe => out.f_e[i] = v,
                _ => {}
            },
        );
    }

    fn tangent(
        &self,
        x: &KernelInput,
        bp: f64,
        gp: f64,
        out: &mut TangentOut,
        scratch: &mut [f64],
    ) {
        run(
            &self.tapes[2],
            &inputs(x, bp, gp),
            scratch,
            |arr, i, v| match arr {
                OutArr::Fr => out.f_r[i] = v,
                OutArr::Fth => out.f_th[i] = v,
                OutArr::Fe => out.f_e[i] = v,
                OutArr::Kee => out.k_ee[i] = v,
                OutArr::DeFrame => out.d_e_frame[i] = v,
                OutArr::KrefE => out.k_ref_e[i] = v,
                OutArr::DrefFrame => out.d_ref_frame[i] = v,
                _ => {}
            },
        );
    }

    fn residual_elastic(&self, x: &KernelInput, f_e: &mut [f64], scratch: &mut [f64]) {
        run(&self.tapes[3], &inputs(x, 0.0, 0.0), scratch, |_, i, v| {
            f_e[i] = v
        });
    }

    fn tangent_elastic(
        &self,
        x: &KernelInput,
        bp: f64,
        gp: f64,
        f_e: &mut [f64],
        k_ee: &mut [f64],
        scratch: &mut [f64],
    ) {
        run(
            &self.tapes[4],
            &inputs(x, bp, gp),
            scratch,
            |arr, i, v| match arr {
                OutArr::Fe => f_e[i] = v,
                OutArr::Kee => k_ee[i] = v,
                _ => {}
            },
        );
    }
}
