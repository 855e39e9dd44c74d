"""Studies built on the kinematic engine: time-domain runs, shock reports, design studies.

This layer may import the kernels (``kinematics``, ``motion``) and :mod:`excavkin.mechanism`,
never ``outputs`` or ``cli``. Import the modules directly, e.g.
``from excavkin.applications.timeline import simulate``.
"""
