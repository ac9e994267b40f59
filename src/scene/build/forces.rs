//! `[[forces]]`: point and follower forces, spring-dampers, rotational
//! spring-dampers and torques, added to the system.

use super::{err, marker, v3};
use crate::runtime::spec::scene::{ForceKind, ForceSpec};
use crate::runtime::{Body, System, TorqueLaw};
use crate::SceneError;
use std::sync::Arc;

pub(super) fn add_force(sys: &mut System<Box<dyn Body>>, f: &ForceSpec) -> Result<(), SceneError> {
    let res = match &f.kind {
        ForceKind::Point {
            at,
            force,
            follower,
        } => {
            let m = marker(sys, at)?;
            let fv = v3(*force);
            if *follower {
                sys.add_follower_force(m, move |_| fv)
            } else {
                sys.add_point_force(m, move |_| fv)
            }
        }
        ForceKind::SpringDamper {
            a,
            b,
            stiffness,
            damping,
            rest_length,
        } => {
            let (a, b) = (marker(sys, a)?, marker(sys, b)?);
            sys.add_spring_damper(a, b, *stiffness, *damping, *rest_length)
        }
        ForceKind::RotationalSpringDamper {
            a,
            b,
            stiffness,
            damping,
            rest_angle,
        } => {
            let (a, b) = (marker(sys, a)?, marker(sys, b)?);
            let law = TorqueLaw::SpringDamper {
                stiffness: *stiffness,
                damping: *damping,
                rest_angle: *rest_angle,
            };
            sys.add_torque(a, b, law)
        }
        ForceKind::Torque { a, b, torque } => {
            let (a, b) = (marker(sys, a)?, marker(sys, b)?);
            let tau = *torque;
            sys.add_torque(a, b, TorqueLaw::Torque(Arc::new(move |_| tau)))
        }
    };
    res.map_err(|e| err(&f.at, e.to_string()))
}
