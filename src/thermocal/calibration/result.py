"""What a calibration found (:class:`CalibrationResult`) and its comparison with a known truth."""

from __future__ import annotations

import contextlib
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from thermocal.calibration.metric import METRIC_NAMES
from thermocal.identification.workflow import jsonable


@dataclass
class CalibrationResult:
    """What the calibration found (see :func:`thermocal.calibration.workflow.calibrate`)."""

    space: Any
    samples: Any
    store_frame: pd.DataFrame
    summary: Any
    surrogate: Any
    ranking: pd.Series
    sobol: pd.DataFrame | None
    critical: list
    optimisation: Any
    nominal_metric: float
    confirmed: dict
    heat: dict
    weather: pd.DataFrame
    validation: dict | None
    morris: pd.DataFrame | None
    truth_comparison: pd.DataFrame | None
    calibrated_building: Any
    timings: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)
    campaign_path: str = ""
    posterior: Any = None
    occupancy: dict = field(default_factory=dict)
    metric: str = "building"
    runs: dict = field(default_factory=dict)
    zoom: dict | None = None
    calibrated_parameters: dict = field(default_factory=dict)
    building_path: str = ""

    def table1(self) -> pd.DataFrame:
        """The paper's Table 1: nominal, min-variance and max-variance critical values."""
        return self.optimisation.table()

    def as_dict(self) -> dict:
        scores = {
            "cv_r2": float(self.surrogate.cv_r2_),
            "cv_rmse": float(self.surrogate.cv_rmse_),
            "kind": type(self.surrogate).__name__,
            "best_params": getattr(self.surrogate, "best_params_", None),
        }
        out = {
            "campaign": self.campaign_path,
            "metric": self.metric,
            "metric_description": METRIC_NAMES[self.metric],
            "metric_unit": "W^2",
            "model_runs": self.runs,
            "samples": {
                "total": int(self.summary.total),
                "successful": int(self.store_frame["error"].isna().sum()),
                "failed": int(self.store_frame["error"].notna().sum()),
                "backend": self.summary.backend,
                "wall_time_s": self.summary.wall_time_s,
            },
            "parameters": self.space.to_frame().reset_index().to_dict(orient="records"),
            "clipped_samples": self.samples.clip_counts.reset_index().to_dict(orient="records"),
            "metamodel": scores,
            "ranking": self.ranking.to_dict(),
            "sobol": None if self.sobol is None else self.sobol.reset_index().to_dict("records"),
            "critical": self.critical,
            "table1": self.table1().reset_index().to_dict(orient="records"),
            "nominal_metric": self.nominal_metric,
            "confirmation": self.confirmed,
            "validation": self.validation,
            "morris": None
            if self.morris is None
            else self.morris.reset_index().to_dict(orient="records"),
            "truth_comparison": None
            if self.truth_comparison is None
            else self.truth_comparison.reset_index().to_dict(orient="records"),
            "posterior": None if self.posterior is None else self.posterior.to_dict(),
            "zoom": self.zoom,
            "occupancy": self.occupancy,
            "timings_s": self.timings,
            "notes": self.notes,
        }
        return jsonable(out)

    def calibrated_building_text(self, directory=None) -> str:
        """The calibrated building as a thermocal building file, ready for ``thermocal
        simulate`` and ``thermocal retrofit``.

        A building imported from an IDF is written as the IDF and the calibrated values
        (:func:`thermocal.multizone.files.idf_with_parameters`): the YAML form cannot hold the
        IDF's schedules, loads, scheduled and wind-driven infiltration or shading, and a file
        without them would be another building (1.7-2.9 K colder on a twin). Any other building
        is written whole.

        Parameters
        ----------
        directory : path-like, optional
            Where the file goes: the IDF is named relative to it (absolute without it).
        """
        import yaml

        from thermocal.calibration.space import parameter_unit
        from thermocal.multizone.elements import element_parameters
        from thermocal.multizone.files import building_to_dict

        source = self.confirmed.get("calibrated", {}).get("source", "meta-model minimum")
        lines = [
            "# thermocal building file: the nominal model with the envelope parameters of the",
            "# lowest confirmed unoccupied variance of the identified heat (calibrated),",
            f"# from the {source}.",
            f"# campaign: {self.campaign_path}",
        ]
        # the values of the body itself (the header and the body always agree)
        building = self.calibrated_building
        values = {**building.parameters(), **element_parameters(building)}
        nominal = self.space.nominal_dict()
        for name in self.space.names:
            if name in values and not np.isclose(values[name], nominal[name], rtol=1e-9):
                lines.append(
                    f"#   {name}: {nominal[name]:.6g} -> {values[name]:.6g} {parameter_unit(name)}"
                )
        if self._from_idf():
            lines.append(
                "# the IDF as imported with the calibrated values (its schedules, loads, "
                "airflows and shading kept)"
            )
            content = self._idf_with_parameters(directory)
        else:
            content = building_to_dict(self.calibrated_building)
        body = yaml.safe_dump(content, sort_keys=False, allow_unicode=True)
        return "\n".join(lines) + "\n" + body

    def _from_idf(self) -> bool:
        """True when the calibrated building was imported from an IDF file (given as such or
        through a building file naming it)."""
        return self._imported_idf() is not None and bool(self.calibrated_parameters)

    def _imported_idf(self) -> Path | None:
        """The IDF the calibrated building was imported from (the importer's record)."""
        from thermocal.multizone.files import imported_idf

        return imported_idf(self.calibrated_building)

    def _idf_with_parameters(self, directory=None) -> dict:
        """The ``idf`` / ``idf_sha256`` / ``parameters`` form of the calibrated building: the
        parameters of the campaign's building file when it names the IDF too, the calibrated
        ones over them."""
        import os

        from thermocal.io.digest import file_sha256

        idf = self._imported_idf()
        name = str(idf)
        if directory is not None:
            with contextlib.suppress(ValueError):  # another drive: keep it absolute
                name = os.path.relpath(idf, Path(directory).resolve())
        return {
            "idf": name,
            "idf_sha256": file_sha256(idf),
            "parameters": {
                **_file_parameters(self.building_path),
                **{k: float(v) for k, v in self.calibrated_parameters.items()},
            },
        }

    def to_files(self, directory) -> list[Path]:
        """calibration.json, table1.csv, campaign export, calibrated building, figures, report."""
        from thermocal.calibration import figures
        from thermocal.calibration.report import write_report
        from thermocal.io.atomic import atomic_write

        directory = Path(directory)
        directory.mkdir(parents=True, exist_ok=True)
        written = [
            atomic_write(
                directory / "calibration.json",
                lambda p: p.write_text(json.dumps(self.as_dict(), indent=2)),
            ),
            atomic_write(directory / "table1.csv", lambda p: self.table1().to_csv(p)),
            atomic_write(directory / "samples.parquet", lambda p: self.store_frame.to_parquet(p)),
            atomic_write(directory / "samples.csv", lambda p: self.store_frame.to_csv(p)),
            atomic_write(
                directory / "calibrated_building.yaml",
                lambda p: p.write_text(self.calibrated_building_text(directory)),
            ),
        ]
        pngs = {}
        from thermocal.report.figures import close, figure_to_png

        for name, fig in figures.calibration_figures(self).items():
            pngs[name] = figure_to_png(fig)
            close(fig)
            written.append(
                atomic_write(directory / f"{name}.png", lambda p, d=pngs[name]: p.write_bytes(d))
            )
        written.append(write_report(self, directory / "report.html", pngs=pngs))
        return written


def truth_comparison(
    names: list[str], space, truth: dict, calibrated: dict, critical=()
) -> pd.DataFrame:
    """Critical parameters vs the generator's truth: moved towards it, share recovered.

    ``recovered = (calibrated - nominal) / (true - nominal)``: 1 = the whole perturbation
    found, 0 = nothing, negative = moved away; NaN for parameters the truth did not perturb.

    Parameters
    ----------
    names : list of str
        Parameters to compare (the critical ones and those the truth perturbed).
    space : ParameterSpace
        Nominal values and units.
    truth : dict
        ``truth.json`` of the demo (``parameters``: name -> {"true": value, ...}).
    calibrated : dict
        Calibrated value per parameter [unit of each parameter].
    critical : sequence of str
        The critical parameters (flagged in the table).
    """
    true = {name: row["true"] for name, row in truth.get("parameters", {}).items()}
    from thermocal.calibration.space import parameter_unit

    nominal_values = space.nominal_dict()
    rows = []
    for name in names:
        nominal = nominal_values[name]
        calibrated_value = calibrated[name]
        target = true.get(name, nominal)
        perturbed = not np.isclose(target, nominal, rtol=1e-9)
        towards = abs(calibrated_value - target) < abs(nominal - target) if perturbed else None
        recovered = (calibrated_value - nominal) / (target - nominal) if perturbed else np.nan
        rows.append(
            {
                "parameter": name,
                "critical": name in critical,
                "unit": parameter_unit(name),
                "nominal": nominal,
                "calibrated": calibrated_value,
                "true": target,
                "perturbed_in_truth": perturbed,
                "moved_towards_truth": towards,
                "recovered_fraction": recovered,
            }
        )
    return pd.DataFrame(rows).set_index("parameter")


def _file_parameters(path) -> dict:
    """The ``parameters`` of a building file naming an IDF (``{}`` for any other file)."""
    from thermocal.multizone.files import named_idf

    named = named_idf(path) if path else None
    return {} if named is None else {str(k): float(v) for k, v in named[1].items()}
