"""The hydraulic excavator, a wing of excavkin: a backhoe front's spec sheet.

===================  ====================================================================
module               what it holds
===================  ====================================================================
``machine``          the machine (front, cylinders, circuits), forward and inverse
                     kinematics, Jacobian, transmission angles
``machine_file``     the machine-file reader (TOML →
[`Machine`][excavkin.excavator.machine.Machine])
``ranges``           working ranges (SAE J1193 / ISO 7135) and the envelope
``forces``           tool forces (ISO 6015 / SAE J1179) with relief capping, force maps
``base``             the base machine: masses, support polygon, tipping lines
``base_file``        the machine file's ``[base]`` and ``[lift]`` tables
``file_reader``      the machine file's field lookups (units, ranges, errors)
``stability``        tipping and slipping (whole-machine equilibrium); forces capped by them
``lift``             lift capacity (ISO 10567): postures, hydraulic capacity, tables
``pin_loads``        pin loads and cylinder forces over the working range, their maxima
``search``           the pattern search shared by ranges and forces
``soil``             soil-cutting resistance: Zelenin's, Balovnev's and McKyes's models
``dig``              resistance along a dig against the available force; the stall point
``dig_plots``        the dig figure (side view; resistance against available force)
``plots``            the working-range and force-map figures
``stability_plots`` the lift chart and the stability and limit maps
``pin_plots``        pin-load heat maps and the chart of the largest loads
``cli``              ``excavkin excavator ranges|forces|ik|stability|lift|pins|cycle|dig``
===================  ====================================================================

The core of excavkin never imports this package.
"""
