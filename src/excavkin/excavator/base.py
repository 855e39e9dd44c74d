"""The excavator's base machine: the machinery layer's
([`excavkin.machinery.base`][excavkin.machinery.base]), under its former import path."""

from excavkin.machinery.base import BaseMachine, Mass, TippingLine, convex_hull

__all__ = ["BaseMachine", "Mass", "TippingLine", "convex_hull"]
