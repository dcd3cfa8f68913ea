"""What people open: matplotlib plots, pyvista renderings, result files (JSON, NPZ, CSV), the report sections
and the HTML report with its browser check. Renderers take finished arrays and a path and compute nothing."""
