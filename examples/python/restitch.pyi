"""Typings of the restitch module (examples/python/restitch_python.cpp)."""
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

__version__: str

Vec3 = Tuple[float, float, float]

class Error(Exception):
    """A failure of restitch: .code is the library's StatusCode name."""
    code: str

def policies() -> Dict[str, List[str]]:
    """The policy names, each list with its default first."""

def samples() -> List[str]:
    """The bundled samples' names."""

class Mesh:
    """A triangle mesh in model units, immutable."""
    def __init__(
        self,
        positions: npt.ArrayLike,
        triangles: npt.ArrayLike,
        normals: Optional[npt.ArrayLike] = None,
        uvs: Optional[Sequence[npt.ArrayLike]] = None,
        colors: Optional[npt.ArrayLike] = None,
        material_ids: Optional[npt.ArrayLike] = None,
    ) -> None: ...
    @property
    def positions(self) -> npt.NDArray[np.float32]: ...
    @property
    def triangles(self) -> npt.NDArray[np.uint32]: ...
    @property
    def normals(self) -> Optional[npt.NDArray[np.float32]]: ...
    @property
    def uvs(self) -> List[npt.NDArray[np.float32]]: ...
    @property
    def colors(self) -> Optional[npt.NDArray[np.float32]]: ...
    @property
    def material_ids(self) -> npt.NDArray[np.int32]: ...
    @property
    def group_ids(self) -> npt.NDArray[np.uint32]: ...
    @property
    def material_names(self) -> List[str]: ...
    @property
    def vertex_count(self) -> int: ...
    @property
    def triangle_count(self) -> int: ...
    @property
    def bounds(self) -> Tuple[Vec3, Vec3]: ...
    def to_glb(self) -> bytes: ...
    def save(self, path: str) -> None: ...

def load(path: str) -> Mesh:
    """Reads a .glb or .gltf file (node transforms applied)."""

def loads(data: bytes) -> Mesh:
    """Reads .glb bytes (or .gltf with embedded buffers)."""

def sample(name: str, **params: float) -> Mesh:
    """A bundled sample generated with these parameters."""

class Analysis:
    """How a mesh repeats; immutable."""
    @property
    def principal_offsets(self) -> List[Vec3]: ...
    @property
    def candidates(self) -> List[Dict[str, Any]]: ...
    @property
    def lattice(self) -> Dict[str, Any]:
        """axes (three vectors), origin, cells per axis, resizable per axis."""
    @property
    def report(self) -> Dict[str, Any]: ...
    def promote(self, offsets: Sequence[Vec3]) -> "Analysis": ...

def analyze(
    mesh: Mesh,
    descriptor: str = "shot",
    matcher: str = "brute_force",
    detector: str = "histogram",
    threads: int = 0,
) -> Analysis:
    """Finds how the mesh repeats (the GIL is released)."""

class Result:
    """One resize."""
    @property
    def mesh(self) -> Mesh: ...
    @property
    def report(self) -> Dict[str, Any]: ...
    @property
    def warnings(self) -> List[Dict[str, str]]: ...
    @property
    def steps(self) -> List[int]: ...

class Retargeter:
    """Resizes one analysed mesh, keeping its caches between requests."""
    def __init__(
        self,
        mesh: Mesh,
        analysis: Analysis,
        label_space: str = "lattice",
        seam_energy: str = "descriptor",
        pivot: str = "origin",
        check: bool = True,
    ) -> None: ...
    def resize(
        self,
        steps: Optional[Sequence[int]] = None,
        size: Optional[Sequence[float]] = None,
        exact: bool = False,
    ) -> Result: ...
    def steps_for_size(self, size: Sequence[float]) -> List[int]: ...
