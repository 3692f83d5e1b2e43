"""vessel-gym: a Gymnasium environment suite for ship manoeuvring."""

__version__ = "0.1.0"
