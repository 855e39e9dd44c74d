"""Machinery: what every machine with hydraulic cylinders shares, below the families' wings.

====================  ===================================================================
module                what it holds
====================  ===================================================================
``machine``           what the layer asks of a family's machine (protocols)
``cylinders``         cylinders and circuits (SI records); lengths arrays ``(n, k)``
``pumps``             pumps and a machine's hydraulics (SI records), for a family's roles
``flows``             speeds and stroke times from flows, hydraulic power
``buckling``          Euler / Johnson buckling of the cylinders' rods
``masses``            a machine's masses as points of its mechanism
``base``              the base machine: masses, support polygon, tipping lines
``equilibrium``       the whole machine on the ground: tipping about any line, slipping
``capped_force``      a tool force capped by pressures and further limits, the limit named
``search``            the vectorised pattern search over cylinder strokes
``pin_loads``         pin loads and cylinder forces of a static state, per member
``designs``           what a family gives for studies of its parameters; a design's model
``soil``              soil-cutting resistance: Zelenin's, Balovnev's and McKyes's models
``file_fields``       machine-file field lookups (units, ranges, messages)
``base_file``         the machine file's ``[base]`` table
``hydraulics_file``   the machine file's ``[hydraulics]`` table, for a family's roles
====================  ===================================================================

A family (the excavator, `excavkin.excavator`) is a wing above this layer: its roles, its
file's family name, its standards and its commands. This package never imports a wing, and
the core's import contracts place it below every wing and above the kinetostatics.
"""
