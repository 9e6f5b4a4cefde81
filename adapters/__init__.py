"""Ecosystem adapters (shapely, trimesh, Open3D, GeoJSON): installed as ``cdt_plugin.adapters``."""
