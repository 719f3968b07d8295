"""The articulated body: MJCF models (``model``) and their dynamics (``dynamics``).

Never imports the fluid (docs/development.md, "Layers"); only ``dynamics``
imports MuJoCo.
"""

from aquagait.body.dynamics import Dynamics
from aquagait.body.mjcf import ModelError
from aquagait.body.model import Joint, Model, load_model

__all__ = ["Dynamics", "Joint", "Model", "ModelError", "load_model"]
