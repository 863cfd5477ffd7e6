"""Chapter 6: an embodied gait learned online on the simulated Oncilla (§6.3-6.6).

Modules: :mod:`.controller` (hidden tanh layer, delay buffer, RLS), :mod:`.protocol`
(the phases of §6.4 as per-step signals), :mod:`.loop` (controller, RLS and physics in
one batched ``lax.scan``), :mod:`.criteria` (success criteria and outcomes),
:mod:`.teacher` (teacher gaits and their screen), :mod:`.sweep` (conditions x seeds as
one dataset) and :mod:`.experiments` (the registered experiments).
"""
