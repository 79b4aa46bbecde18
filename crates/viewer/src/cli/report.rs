//! The JSON frame report. Keys are stable and documented in the README.

use serde_json::{json, Value};
use stereo::{FrameStats, Quality};
use tracer::RayCounts;

/// `{primary, shadow, reflection, total}`.
#[must_use]
pub fn rays(r: &RayCounts) -> Value {
    json!({ "primary": r.primary, "shadow": r.shadow, "reflection": r.reflection, "total": r.total() })
}

/// The `quality` object. PSNR is `null` when the images are identical (infinite PSNR).
#[must_use]
pub fn quality(q: &Quality) -> Value {
    json!({
        "psnr_db": q.psnr_db.is_finite().then_some(q.psnr_db),
        "mean_abs": q.mean_abs,
        "max_abs": q.max_abs,
        "share_over_2_255": q.share_over_2_255,
        "share_not_identical": q.share_not_identical,
    })
}

/// `left`, `right`, `stages` and `ratios` of one frame (or of per-key medians).
#[must_use]
pub fn frame(s: &FrameStats) -> Value {
    let total = (s.left.rays.total() + s.right.rays.total()).max(1) as f64;
    json!({
        "left": { "rays": rays(&s.left.rays), "ms": s.left.ms },
        "right": {
            "rays": rays(&s.right.rays),
            "ms": s.right.ms,
            "pixels": {
                "reprojected": s.pixels.reprojected,
                "retraced_gap": s.pixels.retraced_gap,
                "retraced_edge": s.pixels.retraced_edge,
                // No mode retraces shadow boundaries any more (exact mode casts each
                // pixel's own shadow rays); the key stays, always 0, so that the report's
                // keys are as DESIGN.md lists them.
                "retraced_shadow": 0,
                "traced": s.pixels.traced,
            },
            "reprojected_share": s.pixels.reprojected_share(),
            "sphere_tests": s.sphere_tests,
        },
        "stages": {
            "trace_left_ms": s.stages.trace_left,
            "reproject_ms": s.stages.reproject,
            "retrace_ms": s.stages.retrace,
            "reshade_ms": s.stages.reshade,
        },
        "ratios": {
            "right_rays_over_left": s.right_ray_ratio(),
            "right_ms_over_left": s.right_time_ratio(),
            "left_share_of_rays": s.left.rays.total() as f64 / total,
            "right_share_of_rays": s.right.rays.total() as f64 / total,
        },
    })
}

/// `memory`: the heap bytes that grow with the scene, by part.
pub fn memory(tracer: &tracer::TracerMemory, screen_bins: usize) -> Value {
    json!({
        "snapshot": tracer.snapshot,
        "bvh": tracer.bvh,
        "light_maps": tracer.light_maps,
        "cones": tracer.cones,
        "screen_bins": screen_bins,
        "total": tracer.total() + screen_bins,
    })
}
