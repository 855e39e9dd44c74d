r"""The rope shovel: a wing above the machinery layer.

An electric mining shovel's front — the boom held by its suspension ropes, the saddle block on
the shipper shaft, the dipper handle sliding through it on its rack, the hoist rope from the
hoist drum over the boom-point sheave to the bail, the dipper on the handle — is a general
mechanism with two inputs, the hoist winch and the crowd. This wing adds its machine file
(``family = "shovel"``: motors, gearing, drum and pinion, payload, the crawler base), and what
a shovel is rated by:

* the digging envelope: cutting height and radius, dump height and radius, radius at floor
  level (`excavkin.shovel.envelope`);
* the forces along a dig from the motors' torque and speed: hoist pull, crowd force, bail pull,
  the tooth's path and speed, the digging-resistance margin (`excavkin.shovel.dig`);
* the boom's loads: suspension-rope tension, boom-foot pin, shipper shaft and sheave
  (`excavkin.shovel.loads`).

It reuses the machinery layer (file fields, base, soil models) and never imports another wing.
"""
