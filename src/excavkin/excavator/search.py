"""The stroke search shared by ranges and forces: the machinery layer's
([`excavkin.machinery.search`][excavkin.machinery.search]), under its former import path."""

from excavkin.machinery.search import Evaluate, Progress, maximize_strokes, part

__all__ = ["Evaluate", "Progress", "maximize_strokes", "part"]
