"""Scenarios as data: harbour geometry, start and goal regions, ship, weather ranges (TOML files)."""

from vessel_gym.scenarios.scenario import (
    Area,
    DepthArea,
    GoalRegion,
    Scenario,
    ScenarioError,
    StartRegion,
    Weather,
    builtin_scenarios,
    load_scenario,
    resolve_scenario_path,
    validate,
)

__all__ = [
    "Area",
    "DepthArea",
    "GoalRegion",
    "Scenario",
    "ScenarioError",
    "StartRegion",
    "Weather",
    "builtin_scenarios",
    "load_scenario",
    "resolve_scenario_path",
    "validate",
]
