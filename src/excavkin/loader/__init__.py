r"""The wheel loader: a wing above the machinery layer.

A wheel loader's front linkage (a Z-bar or a parallel-lift linkage: lift arm, bell crank, tilt
link, bucket; lift and tilt cylinders) is a general mechanism; this wing adds its roles
``("lift", "tilt")``, its machine file (``family = "loader"``), the chassis it stands on (two
axles, tyres, an articulation joint, front and rear frame masses, counterweight), and the
standards that rate it:

* dimensions per SAE J732 / ISO 7131 (`excavkin.loader.dimensions`);
* breakout force per SAE J732 / ISO 14397-2 (`excavkin.loader.breakout`);
* static tipping load, straight and at full articulation, and the rated operating capacity per
  SAE J818 / ISO 14397-1 (`excavkin.loader.tipping`).

It reuses the machinery layer (cylinders, circuits, pumps, capped force, mass points, tipping
lines) and never imports another wing.
"""
