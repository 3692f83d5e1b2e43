"""Local flat-earth x/y (north/east, m) <-> WGS-84 latitude/longitude about a reference point.

Harbour-scale scenarios (tens of km) use the tangent-plane approximation with the WGS-84 meridional and
prime-vertical radii of curvature at the reference latitude (error < 1 m over 10 km).
"""

from __future__ import annotations

import math

A_WGS84_M = 6378137.0  # semi-major axis, m
E2_WGS84 = 6.69437999014e-3  # first eccentricity squared, -


def _radii(lat0_deg: float) -> tuple[float, float]:
    s = math.sin(math.radians(lat0_deg))
    w = math.sqrt(1.0 - E2_WGS84 * s * s)
    R_N = A_WGS84_M / w  # prime vertical
    R_M = A_WGS84_M * (1.0 - E2_WGS84) / w**3  # meridional
    return R_M, R_N


def local_to_latlon(
    x_north_m: float, y_east_m: float, lat0_deg: float, lon0_deg: float
) -> tuple[float, float]:
    """Local (north, east) metres about (lat0, lon0) -> (lat, lon) in degrees."""
    R_M, R_N = _radii(lat0_deg)
    lat = lat0_deg + math.degrees(float(x_north_m) / R_M)
    lon = lon0_deg + math.degrees(float(y_east_m) / (R_N * math.cos(math.radians(lat0_deg))))
    return lat, lon


def latlon_to_local(lat_deg: float, lon_deg: float, lat0_deg: float, lon0_deg: float) -> tuple[float, float]:
    """(lat, lon) degrees -> local (north, east) metres about (lat0, lon0)."""
    R_M, R_N = _radii(lat0_deg)
    x = math.radians(lat_deg - lat0_deg) * R_M
    y = math.radians(lon_deg - lon0_deg) * R_N * math.cos(math.radians(lat0_deg))
    return x, y
