r"""The crane: a wing above the machinery layer.

A crane on a carrier: a turntable that slews about a vertical axis, a boom raised by a luffing
cylinder, a jib moved by a second cylinder (a knuckle-boom crane's outer boom folded by its
knuckle cylinder, or a telescopic crane's fly section pushed out by its telescoping cylinder),
the hook hanging below the jib's tip on a hoist rope of n parts, and the carrier standing on
outriggers or crawlers. The booms are a general model (the engine solves every pose); this
wing adds its machine file (``family = "crane"``), the pose at a hook radius
(`excavkin.crane.machine`), the load chart over radius × boom configuration × slew sector with
its hydraulic, hoist and stability limits (`excavkin.crane.chart`, ASME B30.5 para. 5-1.1.1),
the working range (`excavkin.crane.reach`) and the support reactions over a slew
(`excavkin.crane.supports`).

It reuses the machinery layer (cylinders and circuits, the support model and the whole-machine
equilibrium) and never imports another wing.
"""
