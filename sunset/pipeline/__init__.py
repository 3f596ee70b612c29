"""The pipeline: the one layer that chains the stages, strip by strip, as the Cray chained its vector loops.

The Cray-1 ran Max's pipeline 64 elements at a time, the result of one
operation flowing into the next in its registers. Here the stages are
*strip kernels*: each takes a strip of rays or pixels and the data it needs,
returns the strip's result, and never calls another stage. This layer is the
only code that chains them, and the only one that holds threads, worker
processes and the work budget.

The stages (below this layer, side by side)::

    sea's scan line   sunset.vector.heightfield.sea_columns     a strip of scan lines  -> the sea in their depth buffer
    islands           sunset.vector.island_samples.islands_scan a strip of scan lines  -> the islands' depth buffer
    direct rays       sunset.vector.direct (geometry, normals)  a strip of rows        -> points, normals, parts
    reflected rays    sunset.vector.reflect.trace_sea_rays      a strip of rows        -> the final fields
    codes             sunset.tape.codes.encode_strip            a strip of rows        -> 8-bit codes
    exposure          sunset.recorder.dicomed.lookup            a strip of rows        -> RGB through the tables
    RGB shading       sunset.light                              a frame's geometry     -> linear RGB

What chains them (this package):

* the work budget, checked once at each entry (a frame, a cycle, a film, the
  player: :func:`sunset.vector.budget.check_work`; an RGB frame or film:
  :mod:`sunset.pipeline.budget`) and passed down with the scene's sampling,
  never again per stage;
* :mod:`sunset.pipeline.frame`: a frame. The 8-bit path
  (:func:`~sunset.pipeline.frame.code_frame`) keeps only what the codes
  need: after the depth buffer, each strip of rows goes through the direct
  rays, the reflected rays and the codes while it is in the cache (compiled:
  one fused pass per strip, :mod:`sunset.pipeline.fused_numba`; NumPy: the
  same stages in order, as the book shows them). The full
  :class:`~sunset.vector.frame.Frame` (points, normals, directions, the sea's
  bounces) is made when a caller asks for it (:func:`~sunset.pipeline.frame.render`:
  the API, the RGB back end, the diagnostics);
* :mod:`sunset.pipeline.cycle`: a wave cycle's tape, what stays still
  computed once and the frames shared out to worker processes; the film's
  cycle and the player's data;
* :mod:`sunset.pipeline.rgb`: the RGB back end's frame and film: the rays
  traced through this layer, shaded by :mod:`sunset.light`;
* :mod:`sunset.pipeline.workers`: the process pools.

The sea's strip kernels are chosen by the sea's kind, in one place
(:func:`sunset.pipeline.frame.sea_stage`): the wave trains' (the scan line
:func:`sunset.vector.heightfield.sea_columns`, the normals, the reflected rays
:func:`sunset.vector.reflect.trace_sea_rays`) or a wind sea's (its FFT tile's
scan line :func:`sunset.vector.windsea_scan.wind_columns`, normals
:func:`~sunset.vector.windsea_scan.wind_normals`, reflected rays
:func:`sunset.vector.windsea_crests.wind_sea_rays`), kernels with the same
arguments; which twin of each runs, NumPy or compiled, is :mod:`sunset.kernels`'
choice. The trains' kernels refuse a wind sea. A wind sea's strips of rows go
through the stages one after the other: the fused pass knows the trains only.
"""
