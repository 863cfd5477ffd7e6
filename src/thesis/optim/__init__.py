"""Optimisers shared by chapters 3, 4, 6 and 7: PSO (eq. 3.1–3.2, transfer
initialisation of §4.4, lock-step runs and the per-generation comparison of §4.6 in
:mod:`.transfer`) and a CMA-ES adapter, both with a batched ask/tell interface and the
same :class:`History` record. Fitness is always *maximised*."""

from thesis.optim import cmaes as cmaes
from thesis.optim import pso as pso
from thesis.optim import transfer as transfer
from thesis.optim.cmaes import CMAState as CMAState
from thesis.optim.cmaes import cmaes_init as cmaes_init
from thesis.optim.cmaes import run_cmaes as run_cmaes
from thesis.optim.pso import OMEGA as OMEGA
from thesis.optim.pso import PHI_G as PHI_G
from thesis.optim.pso import PHI_P as PHI_P
from thesis.optim.pso import History as History
from thesis.optim.pso import PSOState as PSOState
from thesis.optim.pso import ask as ask
from thesis.optim.pso import best_particles as best_particles
from thesis.optim.pso import normalise as normalise
from thesis.optim.pso import pso_init as pso_init
from thesis.optim.pso import run_pso as run_pso
from thesis.optim.pso import search_space_size as search_space_size
from thesis.optim.pso import tell as tell
from thesis.optim.transfer import compare_generations as compare_generations
from thesis.optim.transfer import run_lockstep as run_lockstep
from thesis.optim.transfer import transfer_init as transfer_init

__all__ = [
    "CMAState", "History", "OMEGA", "PHI_G", "PHI_P", "PSOState", "ask", "best_particles",
    "cmaes", "cmaes_init", "compare_generations", "normalise", "pso", "pso_init",
    "run_cmaes", "run_lockstep", "run_pso", "search_space_size", "tell", "transfer",
    "transfer_init",
]
