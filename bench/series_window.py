"""The window series' extent and window (bench/window_series.py), shared
with bench/gdal_open_bench.py: nested extents centred on 96 W, 37 N; the
window is 1 % of the third map's extent (the conterminous United States'
width and height), centred."""

W, S, E, N = -125.0, 25.0, -67.0, 49.0
CX, CY = (W + E) / 2, (S + N) / 2
WINDOW = (CX - (E - W) * 0.05, CY - (N - S) * 0.05, CX + (E - W) * 0.05, CY + (N - S) * 0.05)
