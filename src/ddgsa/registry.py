"""Name -> class registries filled by a decorator (GSA methods, models)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Generic, TypeVar

from ddgsa.errors import unknown_name_message

T = TypeVar("T", bound=type)


class Registry(dict[str, T], Generic[T]):
    """A dict of registered classes; an unknown name raises ``error`` listing the known ones.

    Parameters
    ----------
    kind : str
        What is registered, for messages ("GSA method", "model").
    error : type of Exception
        The exception raised for an unknown name.
    """

    def __init__(self, kind: str, error: type[Exception]) -> None:
        super().__init__()
        self.kind, self.error = kind, error

    def register(self, name: str) -> Callable[[T], T]:
        """Class decorator registering ``cls`` under ``name`` (sets ``cls.name``)."""

        def deco(cls: T) -> T:
            cls.name = name
            self[name] = cls
            return cls

        return deco

    def lookup(self, name: str) -> T:
        """The class registered as ``name``."""
        try:
            return self[name]
        except KeyError:
            raise self.error(unknown_name_message(self.kind, name, list(self))) from None
