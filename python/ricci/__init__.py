"""ricci: discrete surface Ricci flow and conformal parameterization.

A thin layer over the C++ library: the functions here check the shapes and dtypes of numpy
arrays, convert them, and call the compiled module ``ricci._ricci``. The options and result
classes are the C++ structs, field for field (``FlowOptions(tolerance=1e-8)``).

    V, F, info = ricci.read_mesh("bunny.obj")
    result = ricci.flow(V, F, target="flat", cones={0: "pi/2"})
    param = ricci.parameterize(V, F, cones="auto")
    exact = ricci.common_refinement(ricci.parameterize(V, F, scheme="vertex-scaling"))
    disk = ricci.parameterize(V, F, geometry="hyperbolic")  # chi < 0: uv in the Poincare disk
    sphere = ricci.sphere(V, F)  # closed genus 0: positions on the unit sphere
    s = ricci.spline(V, F)  # manifold spline: s.surface, s.control_net, s.error, s.continuity
    table = ricci.batch(["a.obj", "b.ply"], "out", jobs=4, cones=8)  # a dict per mesh

Errors: ``InvalidInput`` (a ValueError), ``TopologyError`` (an InvalidInput), ``IoError`` (an
OSError), ``SolverError`` (a RuntimeError), all deriving from ``ricci.Error``.
"""

from . import generate
from ._ricci import (
    AffineAtlas,
    BoundaryChart,
    BoundaryMode,
    ChartPacking,
    ChartPackingOptions,
    Component,
    ComponentFlow,
    ComponentInfo,
    CommonRefinement,
    CommonRefinementOptions,
    ComponentMethod,
    ComponentParam,
    Cone,
    ConeMode,
    FreeSeamOptions,
    SeamCurvature,
    SeamMode,
    ConeSelection,
    ConeSelectionOptions,
    ConformalStructure,
    ContinuityReport,
    CutGraph,
    CutMesh,
    Defect,
    DefectKind,
    Distortion,
    Error,
    FlowOptions,
    FlowResult,
    EdgeFlips,
    FlowSolver,
    FlowStatus,
    FlowTimings,
    FuchsianGroup,
    Geometry,
    HyperbolicLayout,
    HyperbolicLayoutOptions,
    HyperbolicParamOptions,
    HyperbolicParamResult,
    InvalidInput,
    IoError,
    IterationRecord,
    Layout,
    Mesh,
    MeshFlowOptions,
    MeshFlowResult,
    MeshFormat,
    MeshInfo,
    MeshParamResult,
    PackedChart,
    PackingInit,
    ParamOptions,
    ParamResult,
    Parameterization,
    PipelineDiagnostics,
    ParamTimings,
    PolishOptions,
    PolishResult,
    Polygons,
    ReadOptions,
    ReadResult,
    RepairOptions,
    RepairResult,
    Scheme,
    SeamTransition,
    SegmentIsometry,
    SolverError,
    SplineError,
    SplineFit,
    SplineOptions,
    SplineResult,
    SphereOptions,
    SphereResult,
    StructureOptions,
    StructureResult,
    Target,
    TargetKind,
    TargetSpec,
    Topology,
    TopologyError,
    UvOverlaps,
    ValidationReport,
    find_uv_overlaps,
    pack_charts,
    parse_cone_list,
    parse_curvature,
    polish_angles,
)
from ._ricci import __version__
from ._batch import batch, batch_summary
from ._flow import flow
from ._mesh import info, polygon_faces, read_mesh, repair, validate, write_mesh, write_obj
from ._param import common_refinement, interpolate_to_refinement, parameterize
from ._sphere import sphere
from ._match import match, morph
from ._spline import spline

__all__ = [
    "batch", "batch_summary", "flow", "info", "parameterize", "common_refinement", "interpolate_to_refinement",
    "CommonRefinement", "CommonRefinementOptions", "read_mesh", "repair", "validate", "write_mesh", "write_obj", "generate",
    "Polygons", "polygon_faces",
    "sphere", "SphereOptions", "SphereResult",
    "match", "morph",
    "spline", "SplineOptions", "SplineResult", "SplineError", "SplineFit", "ContinuityReport",
    "FuchsianGroup", "HyperbolicLayout", "HyperbolicLayoutOptions", "HyperbolicParamOptions",
    "HyperbolicParamResult", "SegmentIsometry",
    "AffineAtlas", "BoundaryChart", "BoundaryMode", "ChartPacking", "ChartPackingOptions",
    "Component", "ComponentFlow", "ComponentInfo", "ComponentMethod", "ComponentParam",
    "Cone", "ConeMode", "FreeSeamOptions", "SeamCurvature", "SeamMode", "ConeSelection", "ConeSelectionOptions", "ConformalStructure", "CutGraph",
    "CutMesh", "Defect", "DefectKind", "Distortion", "Error", "FlowOptions", "FlowResult",
    "EdgeFlips", "FlowSolver", "FlowStatus", "FlowTimings", "Geometry", "InvalidInput", "IoError", "IterationRecord",
    "Layout", "Mesh", "MeshFlowOptions", "MeshFlowResult", "MeshFormat", "MeshInfo", "MeshParamResult", "PackedChart",
    "PackingInit",
    "ParamOptions", "ParamResult", "Parameterization", "PipelineDiagnostics", "ParamTimings", "PolishOptions", "PolishResult", "ReadOptions", "ReadResult", "RepairOptions", "RepairResult",
    "Scheme", "SeamTransition",
    "SolverError", "StructureOptions", "StructureResult", "Target", "TargetKind", "TargetSpec",
    "Topology", "TopologyError", "UvOverlaps", "ValidationReport", "find_uv_overlaps", "pack_charts",
    "parse_cone_list", "parse_curvature", "polish_angles",
]
