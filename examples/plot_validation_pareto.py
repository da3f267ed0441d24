"""
# Speed against accuracy: the Pareto front

A warp is fast but resamples; a direct render is exact but slow. `lenslab.validate` measures the
trade: it renders the target view directly (the reference), renders panoramas of several sizes from
the same eye, warps each into the target with each filter, and compares. The source here is the
noise-free analytic sky, so the errors are the resampling error alone. The Pareto front joins the
settings that no other setting beats on both time and error.

The analytic sky costs almost nothing to evaluate, so here a direct render is as cheap as a warp. With
a ray-traced scene a direct render costs seconds per view (`lenslab validate --scene cornell` runs the
same comparison with the tracer's Cornell box), and one panorama serves every view: that is what the
warp saves.
"""

import matplotlib.pyplot as plt

import lenslab
from lenslab.validate.run import WarpSetting, pareto_front, validate
from lenslab.validate.sources import AnalyticSource

target = lenslab.Camera.from_spec("fisheye:fov=180,mapping=equisolid", (160, 160), pitch=20)
settings = [WarpSetting.parse(s) for s in ("bilinear", "antialias", "bilinear@2x2", "lanczos")]
val = validate(AnalyticSource(), target, pano_sizes=[(256, 128), (512, 256), (1024, 512)], settings=settings,
               reference_spp=16, direct_spp=(1, 4), seed=None, repeat=2, with_flip=False, progress=False, keep_images=False)

for row in sorted(val.rows, key=lambda r: r["seconds"]):
    print(f"{row['label']:32s} {row['seconds'] * 1e3:7.1f} ms   relative L1 {row['l1']:.3%}")

# %%
# Error against time; each point is labelled with its panorama's width. Each warp is timed at its best
# of two runs, so the first run's compilation of the kernels is left out.

fig, ax = plt.subplots(figsize=(8, 5), layout="constrained")
for setting in settings:
    rows = sorted((r for r in val.rows if r.get("setting") == setting.label), key=lambda r: r["seconds"])
    ax.plot([r["seconds"] for r in rows], [100 * r["l1"] for r in rows], marker="o", label=setting.label)
    for r in rows:
        ax.annotate(str(r["pano_size"][0]), (r["seconds"], 100 * r["l1"]), fontsize=7, xytext=(3, 3),
                    textcoords="offset points")
direct = sorted((r for r in val.rows if r["kind"] == "direct"), key=lambda r: r["seconds"])
ax.plot([r["seconds"] for r in direct], [100 * r["l1"] for r in direct], "k--", marker="s", label="direct render")
front = sorted((r for r in val.rows if r["label"] in set(pareto_front(val.rows))), key=lambda r: r["seconds"])
ax.step([r["seconds"] for r in front], [100 * r["l1"] for r in front], where="post", color="k", alpha=0.35,
        linewidth=2, label="Pareto front")
ax.set(xscale="log", yscale="log", xlabel="seconds (panorama render + warp, or direct render)", ylabel="relative L1 vs direct render (%)",
       title="a 160 px equisolid fisheye from the analytic sky")
ax.grid(True, which="both", alpha=0.3)
ax.legend(fontsize=8)
plt.show()
