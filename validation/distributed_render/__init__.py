"""Render one pathtracer image across machines on Dask distributed, merged exactly.

The render's passes are split into ranges; each range is a task that runs
``pathtracer SCENE ... --passes A:B -o part.film`` on a worker and returns the
partial film's bytes; the driver gathers them and runs ``pathtracer merge``,
which makes the image one uninterrupted render would have made, bit for bit.
See README.md in this folder.
"""

from .driver import PartResult, RenderError, plan_passes, remove_orphaned_part_folders, render, split_passes

__all__ = ["PartResult", "RenderError", "plan_passes", "remove_orphaned_part_folders", "render", "split_passes"]
