"""The reproduction's figures as files: each PNG at the dpi asked for and the figure's size, each PDF the figure's
page, legends beside the data, Fig. 3's phase portraits in equal aspect."""

from __future__ import annotations

import pytest

from frictionflow.paper.export import save_figure
from frictionflow.paper.pipeline import FIGURES, figure_jobs
from tests.test_figures_paper import assert_legends_beside_the_data, assert_png, assert_vector


@pytest.fixture(scope="module")
def jobs(data, settings):
    return {stem: (plot, args) for stem, plot, args in figure_jobs(data, settings)}


def test_every_figure_is_drawn(jobs):
    assert set(jobs) == set(FIGURES)


@pytest.mark.parametrize("stem", FIGURES)
def test_png_at_the_dpi_asked_for_and_pdf_at_the_figures_size(jobs, stem, tmp_path):
    plot, args = jobs[stem]
    fig = plot(*args)
    assert_legends_beside_the_data(fig)
    png, pdf = save_figure(fig, tmp_path, stem, dpi=96)
    assert_png(png, fig, 96)
    assert_vector(pdf, fig)


def test_fig3_phase_portraits_are_equal_aspect(jobs):
    plot, args = jobs["fig3"]
    fig = plot(*args)
    assert [ax.get_aspect() for ax in fig.axes] == [1.0, 1.0]
