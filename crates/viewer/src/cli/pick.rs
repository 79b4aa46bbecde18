//! `stereotrace pick [FRAME] --eye left|right --at X,Y`: what one pixel of one eye shows.
//!
//! The scene, its overrides and the eye size are `render`'s flags; FRAME is a frame of the
//! orbit animation as `render --frames` numbers them (scene time `--time` + FRAME/`--fps`).
//! The pixel's primary ray ([`tracer::EyeView::primary_ray`], the very ray the renderer
//! traces for it) is asked for its closest hit ([`Tracer::intersect`]): the sphere the film's
//! object plane records for that pixel. It prints the sphere, the atom it is (its file's
//! fields and coordinates), the ray and the hit point. A pixel outside the eye image is bad
//! input (exit 2); a ray that hits nothing is a [`Miss`] (exit 3), reported on stdout too
//! with `--json`.

use std::fmt::{self, Write as _};

use anyhow::Result;
use glam::Vec3;
use serde_json::{json, Value};
use tracer::{Eye, Ray, Scene, Tracer};

use crate::args::{PickArgs, PickEye};
use crate::pick::atom_of;
use crate::setup::{BadInput, FrameSetup};

/// The pixel's ray hit nothing: exit code 3.
#[derive(Debug)]
pub struct Miss(pub String);

impl fmt::Display for Miss {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Miss {}

/// Runs the command.
pub fn run(args: &PickArgs) -> Result<()> {
    let (w, h) = (args.frame.width, args.frame.height);
    let (x, y) = parse_at(&args.at, (w, h))?;
    if !(args.fps.is_finite() && args.fps > 0.0) {
        return Err(BadInput(format!("--fps {}: must be a number > 0", args.fps)).into());
    }
    let setup = FrameSetup::load(&args.frame, 0)?;
    let time = args.frame.time + args.frame_number.unwrap_or(0) as f32 / args.fps;
    let mut tracer = Tracer::new(&setup.scene, time);
    tracer.set_max_depth(setup.scene.render.max_depth);
    let eye = match args.eye {
        PickEye::Left => Eye::Left,
        PickEye::Right => Eye::Right,
    };
    let ray = setup.camera.view(eye, w, h).primary_ray(x, y);
    let hit = tracer.intersect(&ray, f32::INFINITY);
    let mut report = json!({
        "scene": setup.path.display().to_string(),
        "eye": if eye == Eye::Left { "left" } else { "right" },
        "x": x,
        "y": y,
        "width": w,
        "height": h,
        "time": short(time),
        "ray": { "origin": vec3(ray.origin), "direction": vec3(ray.dir) },
        "hit": hit.is_some(),
    });
    let Some(hit) = hit else {
        if args.json {
            super::print_out(&(serde_json::to_string_pretty(&report)? + "\n"))?;
        }
        return Err(Miss(format!(
            "pick: pixel ({x}, {y}) of the {} eye sees no sphere: its ray misses the scene",
            if eye == Eye::Left { "left" } else { "right" }
        ))
        .into());
    };
    let fields = hit_fields(&setup.scene, time, &ray, hit.object, hit.t);
    if let (Some(o), Value::Object(f)) = (report.as_object_mut(), fields) {
        o.extend(f);
    }
    if args.json {
        super::print_out(&(serde_json::to_string_pretty(&report)? + "\n"))?;
    } else {
        super::print_out(&text(&report))?;
    }
    Ok(())
}

/// `--at X,Y`: two whole numbers, inside the `width` × `height` eye image.
fn parse_at(s: &str, (width, height): (u32, u32)) -> Result<(u32, u32)> {
    let bad = |why: &str| BadInput(format!("--at {s}: {why}"));
    let Some((a, b)) = s.split_once(',') else {
        return Err(bad("expected X,Y: a column and a row, whole numbers, e.g. 640,360").into());
    };
    let number = |t: &str| t.trim().parse::<i64>().map_err(|_| bad(&format!("`{}` is not a whole number", t.trim())));
    let (x, y) = (number(a)?, number(b)?);
    if !(0..i64::from(width)).contains(&x) || !(0..i64::from(height)).contains(&y) {
        return Err(bad(&format!(
            "outside the {width}×{height} eye image (x 0 to {}, y 0 to {})",
            width - 1,
            height - 1
        ))
        .into());
    }
    // Both checked to lie in 0..width and 0..height, which are u32.
    Ok((x as u32, y as u32))
}

/// An f32 vector as JSON numbers ([`short`] each).
fn vec3(v: Vec3) -> [f64; 3] {
    v.to_array().map(short)
}

/// An f32 as the f64 with the same shortest decimal form (47.42, not 47.41999816894531):
/// the file's columns as written.
fn short(v: f32) -> f64 {
    v.to_string().parse().unwrap_or(f64::from(v))
}

/// What the pick hit: the object, the hit point, the sphere, and the atom when the sphere
/// is one.
pub(crate) fn hit_fields(scene: &Scene, time: f32, ray: &Ray, object: u32, t: f32) -> Value {
    let sphere = scene.sphere_at(object as usize, time);
    let atom = atom_of(scene, object as usize).and_then(|(s, k)| {
        let a = scene.structures[s].atom(k)?;
        Some(json!({
            "structure": s,
            "source": scene.structures[s].source,
            "index": k,
            "file_index": a.file_index,
            "chain": a.chain,
            "residue_name": a.residue_name,
            "residue_number": a.residue_number,
            "insertion_code": a.insertion_code.map(String::from),
            "name": a.name,
            "element": a.element.symbol(),
            "b_factor": a.b_factor.map(short),
            "occupancy": a.occupancy.map(short),
            "hetatm": a.hetero,
            "model": a.model,
            "file_position": a.file_position.map(short),
            "operator": a.operator,
        }))
    });
    json!({
        "t": f64::from(t),
        "point": vec3(ray.at(t)),
        "object": object,
        "sphere": { "center": vec3(sphere.center), "radius": short(sphere.radius) },
        "atom": atom,
    })
}

/// The report as text, a line a field.
fn text(r: &Value) -> String {
    let v3 = |v: &Value| {
        let n: Vec<String> = (0..3).map(|i| format!("{:.3}", v[i].as_f64().unwrap_or(f64::NAN))).collect();
        format!("({})", n.join(", "))
    };
    let mut out = format!(
        "{} eye, pixel ({}, {}) of {}×{}\nray: from {} along {}\nhit: sphere {} at t = {:.4}, point {}\n",
        r["eye"].as_str().unwrap_or(""),
        r["x"],
        r["y"],
        r["width"],
        r["height"],
        v3(&r["ray"]["origin"]),
        v3(&r["ray"]["direction"]),
        r["object"],
        r["t"].as_f64().unwrap_or(f64::NAN),
        v3(&r["point"]),
    );
    let a = &r["atom"];
    if a.is_object() {
        let opt = |v: &Value| if v.is_null() { "-".to_owned() } else { v.to_string().trim_matches('"').to_owned() };
        let _ = write!(
            out,
            "atom {} of {}: {} {}{}, atom {} ({}), chain {}{}{}\nB-factor {}, occupancy {}, model {}\nfile coordinates: {}\n",
            a["index"],
            opt(&a["source"]),
            opt(&a["residue_name"]),
            opt(&a["residue_number"]),
            a["insertion_code"].as_str().unwrap_or(""),
            opt(&a["name"]),
            opt(&a["element"]),
            opt(&a["chain"]),
            if a["hetatm"].as_bool() == Some(true) { ", HETATM" } else { "" },
            a["operator"].as_str().map(|o| format!(", assembly operator {o}")).unwrap_or_default(),
            opt(&a["b_factor"]),
            opt(&a["occupancy"]),
            opt(&a["model"]),
            v3(&a["file_position"]),
        );
    } else {
        out += "not an atom: one of the scene's own spheres\n";
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn at_takes_a_pixel_inside_the_image_and_names_the_value_otherwise() {
        assert_eq!(parse_at("0,0", (8, 4)).unwrap(), (0, 0));
        assert_eq!(parse_at(" 7, 3", (8, 4)).unwrap(), (7, 3));
        for (bad, why) in [
            ("8,0", "--at 8,0: outside the 8×4 eye image (x 0 to 7, y 0 to 3)"),
            ("0,4", "--at 0,4: outside the 8×4 eye image"),
            ("-1,2", "--at -1,2: outside"),
            ("1.5,2", "--at 1.5,2: `1.5` is not a whole number"),
            ("12", "--at 12: expected X,Y"),
        ] {
            let e = parse_at(bad, (8, 4)).unwrap_err();
            assert!(e.downcast_ref::<BadInput>().is_some(), "{bad}: bad input, exit 2");
            assert!(e.to_string().starts_with(why), "{bad}: {e}");
        }
    }
}
