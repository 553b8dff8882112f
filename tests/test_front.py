"""The front's Python surface: Trajectory.to_xarray / to_pandas, rich HTML, the new figures
and the animation's geometry. The command line has its own tests (test_cli.py)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import kreisel

TOY = {"I1": 1.75e-4, "I3": 2.0e-5, "m": 0.1, "l": 0.04}
TIPPE_C = 0.4 * 0.02 * 0.02**2


@pytest.fixture(scope="module")
def tippe_run():
    top = kreisel.PlayTop(m=0.02, A=0.8 * TIPPE_C, C=TIPPE_C, s=0.006, rho=0.02,
                          friction=kreisel.Viscous(1.0))  # fmt: skip
    return kreisel.simulate(top, top.state(theta=np.pi - 0.1, psi_dot=150.0), 4.0, rtol=1e-9)


@pytest.fixture(scope="module")
def exact_run():
    top = kreisel.LagrangeTop(**TOY)
    return top.exact(top.state(0.6, psi_dot=300.0), np.linspace(0.0, 0.5, 501))


def test_import_kreisel_loads_no_plotting_or_io_library():
    code = (
        "import sys, kreisel, kreisel.plot, kreisel.animate\n"
        "heavy = {'matplotlib', 'xarray', 'pandas', 'plotly', 'imageio', 'click', 'scipy'}\n"
        "print(sorted(heavy & {m.split('.')[0] for m in sys.modules}))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_to_xarray_keeps_every_column_with_units(tippe_run):
    ds = tippe_run.to_xarray()
    assert ds.sizes["t"] == len(tippe_run)
    assert set(ds.data_vars) == set(tippe_run.columns) - {"t"}
    np.testing.assert_array_equal(ds["quaternion"].values, tippe_run.quaternion)
    np.testing.assert_array_equal(ds["com"].sel(space_axis="z").values, tippe_run.com[:, 2])
    assert ds["normal_force"].attrs["units"] == "N"
    assert list(ds["mode"].values[:3]) == list(tippe_run.mode[:3])
    assert "PlayTop" in ds.attrs["model"]


def test_netcdf_round_trip_through_the_scipy_engine(tmp_path, exact_run):
    import xarray as xr

    path = tmp_path / "t.nc"
    exact_run.to_xarray().to_netcdf(path, engine="scipy")
    with xr.open_dataset(path, engine="scipy") as back:
        np.testing.assert_array_equal(back["theta"].values, exact_run.theta)
        assert back["psi_dot"].attrs["units"] == "rad/s"


def test_to_pandas_splits_vectors_into_named_columns(tippe_run):
    df = tippe_run.to_pandas()
    assert df.index.name == "t" and len(df) == len(tippe_run)
    np.testing.assert_array_equal(df["omega_3"].to_numpy(), tippe_run.omega[:, 2])
    np.testing.assert_array_equal(df["contact_point_y"].to_numpy(), tippe_run.contact_point[:, 1])
    assert "quaternion" not in df.columns


def test_html_views_name_parameters_and_units(tippe_run):
    top = kreisel.LagrangeTop(**TOY)
    page = top._repr_html_()
    assert "kg m²" in page and "sleeping threshold" in page and repr(top) in page
    heavy = kreisel.HeavyTop(I1=2e-3, I2=2e-3, I3=1e-3, m=0.5, com=[0.02, 0, 0])
    assert "kovalevskaya" in heavy._repr_html_()
    assert "a tippe top" in tippe_run.model._repr_html_()
    page = tippe_run._repr_html_()
    assert "normal_force" in page and "<td>N</td>" in page and "slip" in page


def test_euler_rates_from_omega_match_the_exact_solution():
    from kreisel.plot import euler_rates

    top = kreisel.LagrangeTop(**TOY)
    st = top.state(0.6, phi_dot=-4.07, psi_dot=300.0, theta_dot=1.0)
    t = np.linspace(0.0, 0.5, 201)
    sim = kreisel.simulate(top, st, 0.5, t_eval=t)
    ex = top.exact(st, t)
    for got, want in zip(euler_rates(sim), euler_rates(ex)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-6 * np.abs(want).max())


def test_figures_label_their_axes_with_units(exact_run, tippe_run):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from kreisel import plot

    fig = plot.rigid_time_series(exact_run)
    labels = [a.get_ylabel() for a in fig.axes]
    assert all("(" in s for s in labels), labels
    assert fig.axes[-1].get_xlabel() == "time t (s)"
    ax = plot.axis_path_phi_theta(exact_run)
    assert "(rad" in ax.get_xlabel() and "(rad" in ax.get_ylabel()
    assert ax.yaxis_inverted()
    assert len(ax.lines) == 3  # the path and the two turning points
    ax = plot.invariant_drift(exact_run)
    assert ax.get_yscale() == "log" and len(ax.lines) == 3
    ax = plot.contact_track(tippe_run)
    assert ax.get_xlabel() == "x (mm)" and ax.get_ylabel() == "y (mm)"
    ax = plot.invariant_drift(tippe_run)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == [
        "Jellett's J", "E + dissipated"
    ]  # fmt: skip
    plt.close("all")


def test_drift_of_a_zero_Mz_is_measured_against_the_angular_momentum():
    from kreisel._diagnostics import conserved, relative_drift

    top = kreisel.HeavyTop(I1=6e-5, I2=6e-5, I3=1e-4, m=0.15, com=[0, 0, 0.001])
    run = kreisel.simulate(top, top.state(np.pi / 2, psi_dot=2000.0), 0.05)
    drift = {k: relative_drift(y, s).max() for k, _label, y, s in conserved(run)}
    # the axis starts horizontal: Mz(0) is round-off, so Mz against itself says nothing
    assert abs(run.Mz[0]) < 1e-15 * 1e-4 * 2000.0
    assert drift["Mz"] < 1e-12


def test_the_tippe_top_is_drawn_inside_its_sphere():
    from kreisel.animate import shape_of

    top = kreisel.PlayTop(m=0.02, A=0.8 * TIPPE_C, C=TIPPE_C, s=0.006, rho=0.02)
    shape = shape_of(top)
    # the model's only contact is the sphere: no drawn point may reach below the floor
    assert np.hypot(shape.z, shape.r).max() <= top.rho * (1 + 1e-12)


def test_animation_frames_follow_the_exact_solution(exact_run):
    from kreisel.animate import sample
    from kreisel.plot import figure_axis

    f = sample(exact_run, 7)
    ex = exact_run.model.exact(exact_run.state, f.t)
    np.testing.assert_allclose(f.rotation[:, :, 2], figure_axis(ex.theta, ex.phi), atol=1e-12)


def test_animation_frames_interpolate_a_simulation_between_its_steps():
    from kreisel.animate import sample

    top = kreisel.LagrangeTop(**TOY)
    st = top.state(0.6, psi_dot=300.0)
    sim = kreisel.simulate(top, st, 0.5)
    f = sample(sim, 9)
    ex = top.exact(st, f.t)
    axis = np.stack([np.sin(ex.theta) * np.sin(ex.phi), -np.sin(ex.theta) * np.cos(ex.phi),
                     np.cos(ex.theta)], -1)  # fmt: skip
    # slerp between adaptive steps: close to the exact axis, not exact
    np.testing.assert_allclose(f.rotation[:, :, 2], axis, atol=2e-3)


def test_render_gives_the_frames_asked_for(tippe_run):
    from kreisel.animate import render

    calls = []
    images = render(tippe_run, frames=3, size_px=160, progress=calls.append)
    assert len(images) == 3 and calls == [1, 1, 1]
    assert images[0].shape == (160, 160, 3) and images[0].dtype == np.uint8
    assert images[0].std() > 10  # something is drawn


def test_animation_rejects_bad_arguments(exact_run):
    from kreisel.animate import render, to_gif

    with pytest.raises(kreisel.ParameterError, match="frames = 1"):
        render(exact_run, frames=1)
    with pytest.raises(kreisel.ParameterError, match="fps = 0"):
        to_gif(exact_run, "x.gif", fps=0)
    with pytest.raises(kreisel.ParameterError, match="t_start"):
        render(exact_run, frames=2, t_start=-1.0)


def test_diagnostics_are_those_of_the_simulated_states_even_after_an_edit():
    # The diagnostics columns are computed when first read; editing a state column before
    # that must not change them. References: theta from R33 = 1 - 2 (x^2 + y^2) (z-x-z
    # angles), E = (I1 (w1^2 + w2^2) + I3 w3^2) / 2 + m g l cos(theta); the contact point
    # of a play top is G - s e3 - rho ez.
    lag = kreisel.LagrangeTop(**TOY)
    traj = kreisel.simulate(lag, lag.state(0.6, psi_dot=300.0), 0.05)
    q, w = traj.quaternion.copy(), traj.omega.copy()
    traj.quaternion[:] = 0.0
    traj.omega[:] = 0.0
    cos_theta = 1.0 - 2.0 * (q[:, 1] ** 2 + q[:, 2] ** 2)
    np.testing.assert_allclose(np.cos(traj.theta), cos_theta, rtol=0, atol=1e-14)
    kin = 0.5 * (lag.I1 * (w[:, 0] ** 2 + w[:, 1] ** 2) + lag.I3 * w[:, 2] ** 2)
    energy = kin + lag.m * lag.g * lag.l * cos_theta
    np.testing.assert_allclose(traj.energy, energy, rtol=1e-14, atol=0)
    assert list(traj.to_dict()) == traj.columns

    s, rho = 0.006, 0.02
    top = kreisel.PlayTop(m=0.02, A=0.8 * TIPPE_C, C=TIPPE_C, s=s, rho=rho,
                          friction=kreisel.Viscous(1.0))  # fmt: skip
    run = kreisel.simulate(top, top.state(theta=np.pi - 0.1, psi_dot=150.0), 0.05, rtol=1e-9)
    com, q = run.com.copy(), run.quaternion.copy()
    run.com[:] = 0.0
    e3 = np.stack(
        [
            2 * (q[:, 1] * q[:, 3] + q[:, 0] * q[:, 2]),
            2 * (q[:, 2] * q[:, 3] - q[:, 0] * q[:, 1]),
            1 - 2 * (q[:, 1] ** 2 + q[:, 2] ** 2),
        ],
        axis=1,
    )
    np.testing.assert_allclose(run.contact_point, com - s * e3 - [0.0, 0.0, rho], atol=1e-15)
    np.testing.assert_allclose(run.u, e3[:, 2], rtol=0, atol=1e-15)


def test_the_stub_of_the_compiled_module_names_what_it_holds():
    """python/kreisel/_core.pyi documents kreisel._core: the same functions and classes,
    and the same methods on each class (so the stub cannot drift from the bindings)."""
    import ast
    import inspect
    import pathlib

    from kreisel import _core

    tree = ast.parse((pathlib.Path(_core.__file__).parent / "_core.pyi").read_text())
    stub_defs = {n.name for n in tree.body if isinstance(n, ast.FunctionDef)}
    stub_classes = {
        n.name: {m.name for m in n.body if isinstance(m, ast.FunctionDef) and m.name != "__new__"}
        for n in tree.body
        if isinstance(n, ast.ClassDef)
    }
    real_defs = {n for n, o in vars(_core).items() if callable(o) and not inspect.isclass(o)}
    real_classes = {
        n: {m for m in vars(o) if not m.startswith("__")}
        for n, o in vars(_core).items()
        if inspect.isclass(o)
    }
    assert stub_defs == real_defs
    assert stub_classes == real_classes
