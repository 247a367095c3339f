"""Moved to :mod:`validate.stats` (the ground floor: the reference uses it too). Kept as an alias."""

from ..stats import *  # noqa: F403
