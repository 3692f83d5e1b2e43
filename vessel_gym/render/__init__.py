"""pygame chart viewer (top-down, north up). Reads simulation state only; pygame is imported lazily."""

from vessel_gym.render.chart import ChartRenderer

__all__ = ["ChartRenderer"]
