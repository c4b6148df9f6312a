"""The base of every GA operator (selection, crossover, mutation): a readable ``repr``
and the check that the operator can handle a genome's coding."""

from __future__ import annotations

from growsim.errors import UserInputError

__all__ = ["Operator"]


class Operator:
    """Base class: ``role`` names the operator family, ``name`` its registry name,
    ``kinds`` the genome kinds (``"bits"``, ``"real"``) it accepts.

    Examples
    --------
    >>> from growsim.ga.mutation import Gaussian
    >>> Gaussian(sigma=0.1)
    Gaussian(sigma=0.1, rate=None)
    """

    role = "operator"
    name = "operator"
    #: genome kinds the operator accepts
    kinds: tuple[str, ...] = ("bits", "real")

    def __repr__(self) -> str:
        opts = ", ".join(f"{a}={v!r}" for a, v in vars(self).items())
        return f"{type(self).__name__}({opts})"

    def check(self, genome) -> None:
        """Raise :class:`UserInputError` if the operator cannot handle ``genome``."""
        if genome.kind not in self.kinds:
            raise UserInputError(
                f"{self.role} {self.name!r} works on {' or '.join(self.kinds)} genomes, "
                f"not on a {genome.kind} genome"
            )
