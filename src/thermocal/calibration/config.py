"""The campaign file of ``thermocal calibrate`` (YAML, validated with pydantic).

Example (every path is relative to the campaign file)::

    building: clinic.yaml            # thermocal building YAML or EnergyPlus IDF (or "demo:clinic")
    weather: weather.epw             # EPW/TMY3 file
    sensors: sensors.csv             # sensor log (read by thermocal.io.read_measurements)
    mapping: mapping.yaml            # sensor -> zone mapping
    period: {start: 2001-01-01, end: 2001-02-01}
    step: 5min
    identification: {method: inverse, feedback: air}
    occupancy: null
    parameters:
      level: material                # or element (construction resistance / heat capacity)
      infiltration: per_zone         # or building: one factor on every zone's rate
      include: ["material/*", "window/*", "infiltration/*", "zone/*"]
      exclude: []
      default_range: 0.75            # relative half-width (+-75 %)
      ranges: {"*/shgc": 100.0, "*/thickness": 10.0}
    sampling: {method: sobol, samples: 500, seed: 1, zoom: 0}   # zoom: local campaign, 0 = off
    metamodel: {kind: svr, top_k: 10, cv_folds: 5, log_target: false}
    optimisation: {starts: 8, seed: 1}
    validation: null                 # optional {start:, end:} second period
    store: campaign.sqlite           # default: <out>/campaign.sqlite

``weather`` and ``sensors`` are required unless ``building`` is a built-in demo (``demo:...``).
Duplicate keys are rejected, as are unknown keys.
"""

from __future__ import annotations

import datetime as _dt
import difflib
import hashlib
import json
from pathlib import Path
from typing import Annotated, Any, Literal

import pandas as pd
from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    PrivateAttr,
    ValidationError,
    field_validator,
    model_validator,
)

from thermocal.calibration.store import campaign_fingerprint
from thermocal.errors import ThermocalInputError
from thermocal.io.digest import file_sha256
from thermocal.io.heat_flux_log import InSituConfig

__all__ = [
    "CampaignFile",
    "MetamodelSection",
    "OptimisationSection",
    "ParametersSection",
    "Period",
    "SamplingSection",
    "load_campaign",
    "parse_campaign",
]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class Period(_Strict):
    """A time period ``[start, end)`` (dates or date-times, local time of the data)."""

    start: _dt.datetime
    end: _dt.datetime

    @model_validator(mode="after")
    def _ordered(self) -> Period:
        if self.end <= self.start:
            raise ValueError(f"end {self.end} must be after start {self.start}")
        return self


class ParametersSection(_Strict):
    """Which model parameters vary and by how much (relative half-widths, 0.75 = +-75 %)."""

    level: Literal["material", "element"] = "material"
    infiltration: Literal["per_zone", "building"] = "per_zone"
    include: list[str] = Field(default_factory=lambda: ["*"])
    exclude: list[str] = Field(default_factory=list)
    default_range: float = Field(0.75, ge=0.0, allow_inf_nan=False)
    ranges: dict[str, float] = Field(default_factory=dict)

    @field_validator("default_range", mode="before")
    @classmethod
    def _half_width(cls, value: Any) -> Any:
        return _relative_half_width(value, "default_range")

    @field_validator("default_range")
    @classmethod
    def _positive(cls, value: float) -> float:
        if value == 0.0:  # the whole campaign ran, then its bounds were found empty
            raise ValueError(
                "default_range is 0: every parameter would stay at its nominal value; give a "
                "relative half-width (0.5 = +-50 %), and leave out what should not vary with "
                "exclude: [PATTERN]"
            )
        return value

    @field_validator("ranges", mode="before")
    @classmethod
    def _half_widths(cls, value: Any) -> Any:
        if isinstance(value, dict):
            return {k: _relative_half_width(v, f"ranges.{k}") for k, v in value.items()}
        return value

    @field_validator("ranges")
    @classmethod
    def _non_negative(cls, value: dict[str, float]) -> dict[str, float]:
        for pattern, v in value.items():
            if not v >= 0.0 or v == float("inf"):
                raise ValueError(
                    f"range of {pattern!r} is {v}; give a non-negative relative half-width "
                    "(0.75 = +-75 %; values are clipped to physical limits anyway)"
                )
            if v == 0.0:
                raise ValueError(
                    f"range of {pattern!r} is 0: its parameters would stay at their nominal "
                    f"values; leave them out with exclude: [{pattern!r}], or give a relative "
                    "half-width (0.5 = +-50 %)"
                )
        return value

    @field_validator("include")
    @classmethod
    def _some(cls, value: list[str]) -> list[str]:
        if not value:
            raise ValueError("include lists no pattern; use ['*'] for every parameter")
        return value


def _relative_half_width(value: Any, key: str) -> Any:
    """Refuse ``[min, max]`` where a relative half-width belongs, saying what it means."""
    if isinstance(value, list | tuple):
        example = ""
        numbers = [v for v in value if isinstance(v, int | float) and not isinstance(v, bool)]
        if len(value) == 2 and len(numbers) == 2 and numbers[0] < numbers[1]:
            low, high = numbers
            if -1.0 < low < 0.0 < high and abs(low + high) < 1e-9:
                example = f"; for [{low:g}, {high:g}] write {high:g}"
            else:
                example = (
                    "; a range [min, max] in the parameter's unit cannot be given here: choose "
                    "the half-width that covers it around the nominal value"
                )
        raise ValueError(
            f"{key} = {value!r} is a list; ranges are relative half-widths: 0.5 means +-50 % "
            "around the "
            f"nominal value (one number){example}"
        )
    return value


#: largest seed a campaign file may give [-]: scikit-learn's ``random_state`` (the meta-models
#: and the posterior's folds take ``sampling.seed``) stops at 2**32 - 1, and the zoom stage
#: samples with ``sampling.seed + 1``
MAX_SEED = 2**32 - 2


def _seed_in_range(value: int) -> int:
    """Refuse a seed numpy and scikit-learn do not take (below 0 or above :data:`MAX_SEED`).

    Parameters
    ----------
    value : int
        The seed of a campaign file's section [-].

    Returns
    -------
    int
        ``value`` [-].
    """
    if not 0 <= value <= MAX_SEED:
        raise ValueError(
            f"a seed is a whole number from 0 to {MAX_SEED} (e.g. 1; the same seed gives the "
            "same samples)"
        )
    return value


#: the seed of a section (sampling, optimisation, morris), checked when the file is read
Seed = Annotated[int, AfterValidator(_seed_in_range)]

#: fewest samples of a zoom campaign (as of the first one: a meta-model and its
#: cross-validation need them) [-]
ZOOM_MIN_SAMPLES = 10


class SamplingSection(_Strict):
    """Sampler, number of samples and seed; ``zoom``: the samples of the local campaign.

    ``zoom`` (default 0 = off; e.g. 32): after the first calibration, a second batch of that many
    samples (same sampler, seed + 1) uniform in the logarithm of the parameters over a box
    around the first answer (+-3 posterior standard deviations of each log-parameter, at least
    +-10 %, clipped to the sampled range); the meta-model is refitted on them, minimised,
    confirmed with the model and the posterior recomputed (:mod:`thermocal.calibration.zoom`).
    Its runs go to the campaign's store like every analysis run: ``--resume`` and a
    re-analysis read them.
    """

    method: Literal["sobol", "lhs", "halton"] = "sobol"
    samples: int = Field(500, ge=1)
    seed: Seed = 1
    zoom: int = 0

    @field_validator("zoom", mode="before")
    @classmethod
    def _zoom_count(cls, value: Any) -> Any:
        if (
            isinstance(value, bool)
            or not isinstance(value, int)
            or (0 < value < ZOOM_MIN_SAMPLES or value < 0)
        ):
            raise ValueError(
                f"sampling.zoom is the number of samples of the local (zoom) campaign: 0 (off) "
                f"or a whole number of at least {ZOOM_MIN_SAMPLES}, got {value!r}"
            )
        return value


class MetamodelSection(_Strict):
    """Meta-model kind and critical-parameter count.

    ``series_terms``: the form of the series meta-model's hourly regressions in
    ``log(p / p_nominal)`` (it also gives the posterior): ``affine`` (the default, the
    published form), ``quadratic`` (a curvature term per parameter) or ``auto`` (the curvature
    kept when it lowers the out-of-fold hourly error); see
    :class:`thermocal.calibration.surrogate.SeriesSurrogate` and docs/calibration.md for
    what each does on the twins.

    ``series_coordinates``: what those regressions are affine in: ``physical`` (the default:
    each construction's conductance ``1 / (R + films)``, window U and SHGC and air change rates
    themselves, the logarithm of the rest; :mod:`thermocal.calibration.coordinates`) or
    ``log`` (the logarithm of every parameter, the published form).
    """

    kind: Literal["svr", "gp", "series", "auto"] = "auto"
    top_k: int = Field(10, ge=1)
    cv_folds: int = Field(5, ge=2)
    log_target: bool = False
    series_terms: Literal["auto", "affine", "quadratic"] = "affine"
    series_coordinates: Literal["physical", "log"] = "physical"


class MorrisSection(_Strict):
    """Morris screening directly on the model (elementary effects), besides the campaign."""

    trajectories: int = Field(10, ge=2)
    levels: int = Field(4, ge=2)
    seed: Seed = 1


class OptimisationSection(_Strict):
    """Starts and seed of the reduced-model optimisation; trust-region refinement steps; which
    parameters the calibrated model may change (``calibrate``: ``determined``, the default,
    only those the posterior says the data determine; ``all``: every varied one)."""

    starts: int = Field(8, ge=1)
    seed: Seed = 1
    refine: int = Field(8, ge=0)
    calibrate: Literal["determined", "all"] = "determined"


class PosteriorSection(_Strict):
    """Options of the posterior of the calibrated parameters.

    ``discrepancy``: the parameter-like model discrepancy added to the likelihood
    (Brynjarsdottir and O'Hagan 2014), its prior scale from the residual along the parameters'
    shifted signatures (``neighbours``, the default), the whole model-error floor (``floor``),
    that floor shared among the parameters (``shared``), or no discrepancy (``none``: the
    intervals assume the model is exact and are too narrow on buildings it did not generate);
    see :func:`thermocal.calibration.posterior.discrepancy_basis`.

    ``advise``: also say which in-situ measurement (a heat-flux plate on one element, the
    ``in_situ`` section) would determine which parameters: the posterior recomputed with each
    element's expected reading (:mod:`thermocal.calibration.advice`; no simulation).

    ``uncertain``: inputs the campaign does not vary but does not know either, integrated out
    of the posterior (one model run each): a parameter name or pattern -> its relative
    standard uncertainty (``{"infiltration/building/factor": 0.4}``); ``auto`` the building's
    infiltration by 40 % when the campaign varies none; ``{}`` (the default) none
    (:mod:`thermocal.calibration.uncertain`).
    """

    discrepancy: Literal["none", "neighbours", "floor", "shared"] = "neighbours"
    advise: bool = False
    uncertain: Literal["auto"] | dict[str, float] = Field(default_factory=dict)


class CampaignFile(_Strict):
    """A validated campaign file; paths are resolved against the file's folder.

    Use :func:`load_campaign`.  ``path`` and ``text`` are the file and its content.
    """

    building: str
    weather: Path | None = None
    sensors: Path | None = None
    mapping: Path | None = None
    period: Period | None = None
    step: str = "5min"
    identification: dict[str, Any] = Field(default_factory=dict)
    occupancy: dict[str, Any] | Literal["auto", "paper", "data"] | None = None
    metric: Literal["building", "groups"] = "groups"
    parameters: ParametersSection = Field(default_factory=ParametersSection)
    sampling: SamplingSection = Field(default_factory=SamplingSection)
    metamodel: MetamodelSection = Field(default_factory=MetamodelSection)
    optimisation: OptimisationSection = Field(default_factory=OptimisationSection)
    posterior: PosteriorSection = Field(default_factory=PosteriorSection)
    morris: MorrisSection | None = None
    validation: Period | None = None
    store: Path | None = None
    in_situ: dict[str, InSituConfig] = Field(default_factory=dict)

    _path: Path | None = PrivateAttr(default=None)
    _text: str = PrivateAttr(default="")

    @field_validator("step")
    @classmethod
    def _step(cls, value: str) -> str:
        try:
            td = pd.Timedelta(value)
        except (ValueError, TypeError):
            raise ValueError(f"step {value!r} is not a duration such as '5min' or '1h'") from None
        if td <= pd.Timedelta(0):
            raise ValueError(f"step {value!r} must be positive")
        return value

    @model_validator(mode="after")
    def _inputs(self) -> CampaignFile:
        if not self.is_demo:
            missing = [k for k in ("weather", "sensors") if getattr(self, k) is None]
            if missing:
                raise ValueError(
                    f"{' and '.join(missing)} missing: a campaign on your own building needs a "
                    "weather file and the sensor log (or use building: demo:clinic)"
                )
        return self

    # ------------------------------------------------------------------------------------------
    @property
    def is_demo(self) -> bool:
        """True for a built-in demo building (``demo:<name>``)."""
        return self.building.startswith("demo:")

    @property
    def path(self) -> Path | None:
        """The campaign file."""
        return self._path

    @property
    def text(self) -> str:
        """The campaign file's text."""
        return self._text

    @property
    def building_path(self) -> Path | None:
        """Resolved building file, None for a demo."""
        return None if self.is_demo else Path(self.building)

    def step_timedelta(self) -> pd.Timedelta:
        """The time step as a Timedelta [s resolution]."""
        return pd.Timedelta(self.step)

    def problem_settings(self) -> dict[str, Any]:
        """What determines the metric, by name: input files' contents, period, step, options.

        JSON-ready; the files are given by the SHA-256 of their content. A store compares it
        with the settings it was written with and names what changed.
        """
        files = {}
        for key in ("building", "weather", "sensors", "mapping"):
            value = getattr(self, key)
            if value is None:
                files[key] = None
            elif key == "building" and self.is_demo:
                files[key] = value
            else:
                files[key] = file_sha256(value)
                if key == "building":
                    named = _named_idf(Path(value))
                    if named is not None:
                        files["building_idf"] = file_sha256(named)
        return json.loads(
            json.dumps(
                {
                    "files": files,
                    "period": None if self.period is None else self.period.model_dump(mode="json"),
                    "step": str(pd.Timedelta(self.step)),
                    "identification": self.identification,
                    "occupancy": self.occupancy,
                },
                sort_keys=True,
                default=str,
            )
        )

    def problem_fingerprint(self) -> str:
        """SHA-256 of :meth:`problem_settings`.

        Changes to the building, weather, sensor or mapping files, the period, the step, the
        identification or occupancy options change it; the parameter, sampling, meta-model,
        optimisation and store sections do not.
        """
        return hashlib.sha256(
            json.dumps(self.problem_settings(), sort_keys=True, default=str).encode()
        ).hexdigest()

    def fingerprint(self, *, samples: int | None = None) -> str:
        """SHA-256 of the campaign definition (problem, parameters and sampling sections).

        Parameters
        ----------
        samples : int, optional
            Sample count overriding ``sampling.samples`` (the ``--samples`` option) [-].

        Notes
        -----
        The store written by the runner should use
        :func:`~thermocal.calibration.store.campaign_definition` with the actual parameter
        space (nominal values, ranges, limits) and ``problem=self.problem_fingerprint()``; this
        method is a cheaper summary from the file alone.
        """
        sampling = self.sampling.model_dump()
        sampling.pop("zoom")  # the zoom campaign is a stage of the analysis, not of the first one
        if samples is not None:
            sampling["samples"] = int(samples)
        return campaign_fingerprint(
            {
                "problem": self.problem_fingerprint(),
                "parameters": self.parameters.model_dump(),
                "sampling": sampling,
            }
        )


def _named_idf(path: Path) -> Path | None:
    """The IDF a building file names (``idf:``, docs/multizone-file.md), if it names one and
    it exists: its content determines the campaign's problem as much as the file's."""
    from thermocal.multizone.files import named_idf

    named = named_idf(path)
    return named[0] if named is not None and named[0].is_file() else None


# ----------------------------------------------------------------------------------------------
# reading
# ----------------------------------------------------------------------------------------------
def _known_keys(loc: tuple) -> list[str]:
    model: Any = CampaignFile
    for part in loc[:-1]:
        field = model.model_fields.get(str(part)) if hasattr(model, "model_fields") else None
        if field is None:
            return []
        ann = field.annotation
        model = next(
            (a for a in getattr(ann, "__args__", (ann,)) if hasattr(a, "model_fields")), None
        )
        if model is None:
            return []
    return list(model.model_fields)


def _format_errors(exc: ValidationError, source: str) -> str:
    lines = []
    for err in exc.errors():
        loc = ".".join(str(p) for p in err["loc"]) or "(top level)"
        msg = err["msg"]
        if err["type"] == "extra_forbidden":
            close = difflib.get_close_matches(str(err["loc"][-1]), _known_keys(err["loc"]), n=1)
            hint = f"did you mean {close[0]!r}? " if close else ""
            msg = f"unknown key; {hint}remove it or check its spelling"
        elif err["type"] == "missing":
            msg = "required key missing"
        elif "input" in err and not isinstance(err["input"], dict | list):
            msg = f"{msg} (got {err['input']!r})"
        lines.append(f"  {loc}: {msg}")
    return f"campaign file {source} is invalid:\n" + "\n".join(lines)


def parse_campaign(
    data: Any, *, base_dir: Path | str = ".", source: str = "<campaign>"
) -> CampaignFile:
    """Validate a parsed campaign mapping; relative paths are resolved against ``base_dir``.

    Parameters
    ----------
    data : dict
        The parsed YAML.
    base_dir : path-like
        Folder of the campaign file.
    source : str
        Name of the file for messages.

    Returns
    -------
    CampaignFile

    Raises
    ------
    ThermocalInputError
        Listing every invalid key, or naming a missing input file.
    """
    if not isinstance(data, dict):
        raise ThermocalInputError(
            f"campaign file {source} must be a YAML mapping of keys (building:, weather:, ...), "
            f"got {type(data).__name__}"
        )
    base = Path(base_dir)
    try:
        campaign = CampaignFile.model_validate(data)
    except ValidationError as exc:
        raise ThermocalInputError(_format_errors(exc, source)) from None
    updates: dict[str, Any] = {}
    for key in ("weather", "sensors", "mapping", "store"):
        value = getattr(campaign, key)
        if value is not None and not Path(value).is_absolute():
            updates[key] = base / value
    if not campaign.is_demo and not Path(campaign.building).is_absolute():
        updates["building"] = str(base / campaign.building)
    if updates:
        campaign = campaign.model_copy(update=updates)
    if campaign.in_situ and campaign.parameters.level != "element":
        raise ThermocalInputError(
            f"campaign file {source}, key 'in_situ': in-situ measurements give construction "
            "resistances, element-level parameters: set parameters.level: element"
        )
    for name, spec in campaign.in_situ.items():
        if spec.component is not None:
            raise ThermocalInputError(
                f"campaign file {source}, key 'in_situ.{name}.component': the parameter's name "
                "says which construction was measured; remove the key"
            )
        if not name.startswith("construction/") or not name.endswith("/resistance"):
            raise ThermocalInputError(
                f"campaign file {source}, key 'in_situ.{name}': an in-situ measurement gives a "
                "construction's thermal resistance; name it construction/<name>/resistance "
                "(element-level parameters, parameters.level: element)"
            )
        if spec.u_value is not None or (spec.file is not None and spec.temperatures == "air"):
            if spec.flow is None:
                raise ThermocalInputError(
                    f"campaign file {source}, key 'in_situ.{name}': from a U-value (air "
                    "temperatures) the resistance needs ISO 6946's surface resistances: give "
                    "flow: horizontal (walls), upward (roofs) or downward (floors), or log the "
                    "surface temperatures (temperatures: surface)"
                )
        if spec.file is not None and not Path(spec.file).is_absolute():
            spec.file = base / spec.file
        if spec.file is not None and not Path(spec.file).is_file():
            raise ThermocalInputError(
                f"campaign file {source}, key 'in_situ.{name}.file': file {spec.file} not found "
                "(paths are relative to the campaign file)"
            )
    for key in ("building", "weather", "sensors", "mapping"):
        value = getattr(campaign, key)
        if value is None or (key == "building" and campaign.is_demo):
            continue
        if not Path(value).is_file():
            raise ThermocalInputError(
                f"campaign file {source}, key '{key}': file {value} not found (paths are "
                "relative to the campaign file)"
            )
    return campaign


def load_campaign(path: Path | str) -> CampaignFile:
    """Read and validate a campaign file.

    Parameters
    ----------
    path : path-like
        The YAML campaign file.

    Returns
    -------
    CampaignFile
        With ``path`` and ``text`` set and every path resolved.

    Raises
    ------
    ThermocalInputError
        Missing file, invalid YAML, duplicate or unknown keys, bad values (the message names the
        file and the key).
    """
    from thermocal.io.yamlfile import read_yaml

    path = Path(path)
    data = read_yaml(path, what="campaign file")
    text = path.read_text(encoding="utf-8")
    campaign = parse_campaign(data, base_dir=path.parent, source=str(path))
    campaign._path = path
    campaign._text = text
    return campaign
