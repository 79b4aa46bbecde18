//! `stereotrace render`: one stereo frame to PNG files and an optional JSON report.

use anyhow::Result;
use serde_json::json;
use stereo::{mask_color, Options, Quality, StereoFrame};
use tracer::{render_eye, Eye, Film, Tracer};

use crate::cli::RenderArgs;
use crate::png_out::write_png;
use crate::report;
use crate::setup::{BadInput, FrameSetup};

/// Runs the command.
pub fn run(args: &RenderArgs) -> Result<()> {
    if args.left.is_none() && args.right.is_none() && args.mask.is_none() && !args.json {
        return Err(BadInput("nothing to do: give --left, --right, --mask and/or --json".into()).into());
    }
    for path in [&args.left, &args.right, &args.mask].into_iter().flatten() {
        check_output_dir(path)?;
    }
    let setup = FrameSetup::load(&args.frame, 1)?;
    let (w, h) = (args.frame.width, args.frame.height);
    let tracer = Tracer::new(&setup.scene, args.frame.time);
    let opts = Options { mode: args.mode, retrace_edges: args.retrace_edges };
    let mut frame = StereoFrame::new();
    let stats = frame.render(&tracer, &setup.camera, w, h, opts);

    if let Some(p) = &args.left {
        write_png(p, w, h, &frame.left().rgb)?;
    }
    if let Some(p) = &args.right {
        write_png(p, w, h, &frame.right().rgb)?;
    }
    if let Some(p) = &args.mask {
        let mask: Vec<u32> = frame.mask().iter().map(|&c| mask_color(c)).collect();
        write_png(p, w, h, &mask)?;
    }
    if args.json {
        let mut reference = Film::new(w, h);
        render_eye(&tracer, &setup.camera.view(Eye::Right, w, h), &mut reference);
        let q = Quality::compare(&frame.right().rgb, &reference.rgb);
        let mut out = json!({
            "scene": setup.path.display().to_string(),
            "width": w,
            "height": h,
            "mode": args.mode.name(),
            "retrace_edges": args.retrace_edges,
            "ipd": setup.camera.ipd,
            "distance": setup.camera.distance,
            "depth": setup.scene.render.max_depth,
            "time": args.frame.time,
            "threads": rayon::current_num_threads(),
            "quality": report::quality(&q),
        });
        if let (Some(o), serde_json::Value::Object(f)) = (out.as_object_mut(), report::frame(&stats)) {
            o.extend(f);
        }
        println!("{}", serde_json::to_string_pretty(&out)?);
    }
    Ok(())
}

/// Fails before any work if an output's directory is missing.
fn check_output_dir(path: &std::path::Path) -> Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => std::path::Path::new("."),
    };
    if dir.is_dir() {
        Ok(())
    } else {
        Err(BadInput(format!("{}: directory {} does not exist", path.display(), dir.display())).into())
    }
}
