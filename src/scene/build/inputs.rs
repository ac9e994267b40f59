//! `[[inputs]]`: the system's inputs (start values), and the torques and
//! forces they drive; drive-acceleration inputs perturb their joint's
//! driver ([`super::joints`]).

use super::forces::table_value;
use super::{driver, err, marker, v3};
use crate::runtime::spec::scene::{ForceProfile, InputKind, SceneSpec};
use crate::runtime::{Body, ForceAxes, ForceElement, System, TorqueLaw};
use crate::scene::model::Input;
use crate::SceneError;
use std::sync::Arc;

/// Add the inputs to `sys` (indices `0..`, in file order) and describe
/// them for the scene: the start value is the profile's value at `t = 0`
/// when there is a profile.
pub(super) fn add_inputs(
    spec: &SceneSpec,
    sys: &mut System<Box<dyn Body>>,
) -> Result<Vec<Input>, SceneError> {
    let mut out = Vec::new();
    for (k, i) in spec.inputs.iter().enumerate() {
        let profile: Option<Arc<dyn Fn(f64) -> f64 + Send + Sync>> = match &i.profile {
            None => None,
            Some(ForceProfile::Drive(p)) => {
                let d = driver(p);
                Some(Arc::new(move |t| d.eval(t)[0]))
            }
            Some(ForceProfile::Table(rows)) => {
                let rows = rows.clone();
                Some(Arc::new(move |t| table_value(&rows, t)))
            }
        };
        let start = profile.as_ref().map_or(i.start, |p| p(0.0));
        let index = sys
            .add_input(start)
            .map_err(|e| err(&i.at, e.to_string()))?;
        debug_assert_eq!(index, k);
        out.push(Input {
            name: i.name.clone(),
            start,
            kind: i.kind.clone(),
            profile,
        });
    }
    Ok(out)
}

/// The torques and forces of the torque and force inputs (after the
/// scene's forces, in file order).
pub(super) fn add_input_loads(
    spec: &SceneSpec,
    sys: &mut System<Box<dyn Body>>,
) -> Result<(), SceneError> {
    for (k, i) in spec.inputs.iter().enumerate() {
        let res = match &i.kind {
            InputKind::Torque { joint } => {
                let j = &spec.joints[*joint];
                let a =
                    j.a.as_ref()
                        .ok_or_else(|| err(&i.at, "a revolute joint has two markers"))?;
                let (a, b) = (marker(sys, a)?, marker(sys, &j.b)?);
                sys.add_torque(a, b, TorqueLaw::Input(k))
            }
            InputKind::Force {
                at,
                direction,
                follower,
            } => {
                let m = marker(sys, at)?;
                sys.add_force(ForceElement::Input {
                    marker: m,
                    direction: v3(*direction),
                    axes: if *follower {
                        ForceAxes::Marker
                    } else {
                        ForceAxes::Global
                    },
                    input: k,
                })
            }
            InputKind::DriveAcceleration { .. } => Ok(()),
        };
        res.map_err(|e| err(&i.at, e.to_string()))?;
    }
    Ok(())
}
