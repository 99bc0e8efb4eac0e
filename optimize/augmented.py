"""The PHR augmented Lagrangian now lives in `jaxdamp.augmented` (the library's band of admissible
histories uses it, and the library must not import optimize/); re-exported here for optimize/."""

from jaxdamp import ALConfig, ALState, al_init, al_update, al_value_and_grad

__all__ = ["ALConfig", "ALState", "al_init", "al_update", "al_value_and_grad"]
