//! `timewarp --motion yaw=30,x=0.3`: a head moving at constant speed from the scene's pose,
//! the motion the timewarp experiment warps traced frames across.
//!
//! The turn is in degrees a second (yaw to the right, pitch up, as [`Camera`] turns); the
//! translation in scene units a second along the axes of the head as it starts (x right,
//! y up, z forward), so the head moves on a straight line while it turns, as a walk does
//! when the eyes sweep across a room. The pitch stops at ±[`MAX_PITCH`] degrees, as the
//! viewer's does.

use std::fmt;
use std::str::FromStr;

use glam::Vec3;
use tracer::Camera;

/// The pitch a moving head stops at, degrees (the viewer's limit: never straight up or down).
pub const MAX_PITCH: f32 = 89.0;

/// Largest turn rate accepted, degrees a second (ten turns a second).
pub const MAX_TURN_RATE: f32 = 3600.0;

/// A head's constant motion.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion {
    /// Turn about the vertical, degrees a second; positive turns right.
    pub yaw: f32,
    /// Tilt, degrees a second; positive looks up.
    pub pitch: f32,
    /// Velocity in the starting head's frame (x right, y up, z forward), scene units a second.
    pub velocity: Vec3,
}

/// The keys `--motion` takes, in the order [`Motion`]'s `Display` writes them.
const KEYS: [&str; 5] = ["yaw", "pitch", "x", "y", "z"];

impl FromStr for Motion {
    type Err = String;

    /// `key=value` pairs separated by commas, keys from `yaw`, `pitch`, `x`, `y`, `z`, each
    /// at most once; the keys not given are 0.
    fn from_str(s: &str) -> Result<Self, String> {
        let expected = "expected KEY=NUMBER pairs separated by commas, keys yaw, pitch (degrees a second), x, y, z (scene units a second), e.g. yaw=30,x=0.3";
        let mut values: [Option<f32>; 5] = [None; 5];
        for part in s.split(',').map(str::trim) {
            let Some((key, value)) = part.split_once('=') else {
                return Err(format!("`{s}`: `{part}` has no `=`: {expected}"));
            };
            let (key, value) = (key.trim(), value.trim());
            let Some(k) = KEYS.iter().position(|&known| known == key) else {
                return Err(format!("`{s}`: unknown key `{key}`: {expected}"));
            };
            let v: f32 = value.parse().map_err(|_| format!("`{s}`: {key}=`{value}` is not a number: {expected}"))?;
            if !v.is_finite() {
                return Err(format!("`{s}`: {key}={value}: must be a finite number"));
            }
            if k < 2 && v.abs() > MAX_TURN_RATE {
                return Err(format!("`{s}`: {key}={value}: a turn of at most {MAX_TURN_RATE} degrees a second"));
            }
            if values[k].replace(v).is_some() {
                return Err(format!("`{s}`: `{key}` is given twice"));
            }
        }
        let [yaw, pitch, x, y, z] = values.map(|v| v.unwrap_or(0.0));
        Ok(Self { yaw, pitch, velocity: Vec3::new(x, y, z) })
    }
}

impl fmt::Display for Motion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let values = [self.yaw, self.pitch, self.velocity.x, self.velocity.y, self.velocity.z];
        let given: Vec<String> =
            KEYS.iter().zip(values).filter(|&(_, v)| v != 0.0).map(|(k, v)| format!("{k}={v}")).collect();
        if given.is_empty() {
            f.write_str("still")
        } else {
            f.write_str(&given.join(","))
        }
    }
}

impl Motion {
    /// The head pose `seconds` after `start`: turned by the rates, moved along the starting
    /// head's axes, the pitch held within ±[`MAX_PITCH`]. The stereo parameters (IPD,
    /// distance, field of view) stay `start`'s.
    #[must_use]
    pub fn pose(&self, start: &Camera, seconds: f64) -> Camera {
        let t = seconds as f32;
        Camera {
            position: start.position + start.world_from_head() * (self.velocity * t),
            yaw_deg: start.yaw_deg + self.yaw * t,
            pitch_deg: (start.pitch_deg + self.pitch * t).clamp(-MAX_PITCH, MAX_PITCH),
            ..*start
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_keys_given_and_leaves_the_rest_at_zero() {
        let m: Motion = "yaw=30, x=0.3".parse().unwrap();
        assert_eq!(m, Motion { yaw: 30.0, pitch: 0.0, velocity: Vec3::new(0.3, 0.0, 0.0) });
        let m: Motion = "pitch=-5,z=1e-1,y=2".parse().unwrap();
        assert_eq!((m.pitch, m.velocity), (-5.0, Vec3::new(0.0, 2.0, 0.1)));
        assert_eq!(m.to_string(), "pitch=-5,y=2,z=0.1", "written back in key order");
        assert_eq!("yaw=0".parse::<Motion>().unwrap().to_string(), "still");
    }

    #[test]
    fn bad_motions_are_refused_naming_the_part() {
        let err = |s: &str| s.parse::<Motion>().unwrap_err();
        assert!(err("roll=3").starts_with("`roll=3`: unknown key `roll`: expected KEY=NUMBER"), "{}", err("roll=3"));
        assert!(err("yaw=fast").starts_with("`yaw=fast`: yaw=`fast` is not a number"), "{}", err("yaw=fast"));
        assert!(err("yaw").starts_with("`yaw`: `yaw` has no `=`"), "{}", err("yaw"));
        assert!(err("yaw=30,").contains("`` has no `=`"), "a trailing comma: {}", err("yaw=30,"));
        assert_eq!(err("x=1,x=2"), "`x=1,x=2`: `x` is given twice");
        assert_eq!(err("x=inf"), "`x=inf`: x=inf: must be a finite number");
        assert!(err("yaw=4000").contains("at most 3600 degrees a second"));
    }

    /// Closed form: a quarter turn a second with one unit a second to the right reaches yaw
    /// 90° after a second, one unit along the starting head's right (+x), whatever the turn.
    #[test]
    fn the_pose_turns_and_moves_along_the_starting_axes() {
        let start = Camera { position: Vec3::new(0.0, 1.0, 0.0), yaw_deg: 90.0, ..Camera::default() };
        let m = Motion { yaw: 90.0, pitch: 100.0, velocity: Vec3::new(1.0, 0.0, 0.0) };
        let p = m.pose(&start, 1.0);
        assert!((p.yaw_deg - 180.0).abs() < 1e-5 && p.pitch_deg == MAX_PITCH, "{p:?}");
        // The starting head faces +x (yaw 90°), so its right is −z.
        assert!((p.position - Vec3::new(0.0, 1.0, -1.0)).length() < 1e-5, "{:?}", p.position);
        assert_eq!((p.ipd, p.distance, p.fov_deg), (start.ipd, start.distance, start.fov_deg));
        assert_eq!(m.pose(&start, 0.0), start, "at 0 s the scene's pose");
    }
}
