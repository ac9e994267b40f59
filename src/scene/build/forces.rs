//! `[[forces]]`: point and follower forces, spring-dampers, rotational
//! spring-dampers and torques, added to the system.

use super::{driver, err, marker, v3};
use crate::runtime::nalgebra::Vector3;
use crate::runtime::spec::scene::{ForceKind, ForceProfile, ForceSpec};
use crate::runtime::{Body, System, TorqueLaw};
use crate::SceneError;
use std::sync::Arc;

pub(super) fn add_force(sys: &mut System<Box<dyn Body>>, f: &ForceSpec) -> Result<(), SceneError> {
    let res = match &f.kind {
        ForceKind::Point {
            at,
            force,
            follower,
            profile,
        } => {
            let m = marker(sys, at)?;
            let fv = v3(*force);
            let f = point_force(fv, profile.as_ref());
            if *follower {
                sys.add_follower_force(m, f)
            } else {
                sys.add_point_force(m, f)
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

/// `F(t) = f(t) force` (`force` without a profile), evaluated without
/// allocating: a drive profile's value, or the table's piecewise-linear
/// value found by binary search.
fn point_force(
    fv: Vector3<f64>,
    profile: Option<&ForceProfile>,
) -> Box<dyn Fn(f64) -> Vector3<f64> + Send + Sync> {
    match profile {
        None => Box::new(move |_| fv),
        Some(ForceProfile::Drive(p)) => {
            let d = driver(p);
            Box::new(move |t| d.eval(t)[0] * fv)
        }
        Some(ForceProfile::Table(rows)) => {
            let rows = rows.clone();
            Box::new(move |t| table_value(&rows, t) * fv)
        }
    }
}

/// The piecewise-linear function through `rows` (`[t, f]`, times strictly
/// increasing, at least one row) at `t`: the first value before the first
/// time, the last after the last, linear in between (a row's own value at
/// its time, exactly). The weights `1 − w`, `w` keep the value between
/// the two rows' (no overflow of `f1 − f0`; the loader checked that the
/// times span a finite interval, so `t1 − t0` is finite).
pub(super) fn table_value(rows: &[[f64; 2]], t: f64) -> f64 {
    // The first row whose time is after t.
    let i = rows.partition_point(|r| r[0] <= t);
    if i == 0 {
        return rows[0][1];
    }
    let [t0, f0] = rows[i - 1];
    match rows.get(i) {
        None => f0,
        Some(&[t1, f1]) => {
            let w = (t - t0) / (t1 - t0);
            f0 * (1.0 - w) + f1 * w
        }
    }
}

#[cfg(test)]
mod tests {
    use super::table_value;

    #[test]
    fn a_table_is_held_before_and_after_and_linear_between() {
        let rows = [[0.0, 1.0], [1.0, 3.0], [3.0, -1.0]];
        assert_eq!(table_value(&rows, -5.0), 1.0);
        assert_eq!(table_value(&rows, 0.0), 1.0);
        assert_eq!(table_value(&rows, 0.5), 2.0);
        assert_eq!(table_value(&rows, 1.0), 3.0);
        assert_eq!(table_value(&rows, 2.0), 1.0);
        assert_eq!(table_value(&rows, 3.0), -1.0);
        assert_eq!(table_value(&rows, 1e9), -1.0);
        assert_eq!(table_value(&[[2.0, 7.0]], 1.0), 7.0);
        assert_eq!(table_value(&[[2.0, 7.0]], 3.0), 7.0);
    }
}
