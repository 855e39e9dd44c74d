"""The hydraulic excavator, a wing of excavkin: a backhoe front's spec sheet.

==================  =====================================================================
module              what it holds
==================  =====================================================================
``machine``         the machine (front, cylinders, circuits), forward and inverse
                    kinematics, Jacobian, transmission angles
``machine_file``    the machine-file reader (TOML → :class:`~excavkin.excavator.machine.Machine`)
``ranges``          working ranges (SAE J1193 / ISO 7135) and the envelope
``forces``          tool forces (ISO 6015 / SAE J1179) with relief capping, force maps
``search``          the pattern search shared by ranges and forces
``plots``           the working-range and force-map figures
``cli``             ``excavkin excavator ranges|forces|ik``
==================  =====================================================================

The core of excavkin never imports this package.
"""
