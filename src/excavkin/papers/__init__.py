"""The source papers, a wing of excavkin: one package per paper.

Each package holds the paper's closed-form reference formulas (``reference``, its printed
misprints corrected and documented; pure NumPy, independent of the engine), its study of the
engine against the paper (``study``), its figures (``figures``) and its
``excavkin reproduce`` command (``cli``). What they share is in `excavkin.papers.common`
and `excavkin.papers.figures`.

==============  ==========================================================================
package         paper
==============  ==========================================================================
``mo100``       Eremyants & Raiymbekova: the MO-100 crank-rocker hammer's reactions
``pasika``      Pasika & Koruniak: the cylinder–rocker module with an internal driving link,
                and its follow-up comparison of motion laws
``rope_shovel`` Maksimov: the EO-4112 rope backhoe's bucket-turning mechanism
``arm_vector``  the excavator arm's vector model
==============  ==========================================================================

The core of excavkin never imports this package.
"""
