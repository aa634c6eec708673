# %% [markdown]
# # The report's claims against what we measure, and its errata
#
# The verdict first: how many of the report's claims the notebooks
# reproduce, and how many of its suggestions they build.  Every number in
# the tables below is read from the data the earlier notebooks wrote; none
# is typed (how, at the end).

# %%
import sys

from IPython.display import HTML, display

sys.path.insert(0, "../scripts")  # outputs.py: data/ and figures/; claims.py: these tables
import claims
import outputs

# %%
measured = claims.Measured()  # data/*.csv, each read once
table = claims.claims_table(measured)
outputs.save_data(table, "claims")
counts = table.kind.value_counts()
print(outputs.wrapped(f"{len(table)} rows: " + ", ".join(
    f"{counts.get(kind, 0)} {kind}" for kind in claims.KINDS)))

# %% [markdown]
# *Reproduced*, *partly* and *not reproduced* judge what the report claims;
# *built* and *proved* answer what it suggests (a method built and
# measured, a proof); *beyond the report* marks findings it does not make,
# which cite no section of the report.  None of the report's claims fails
# outright: its two partial ones are the bound of $10^{-3}$ on the
# cannonball's errors (the ellipse's position error passes it) and its
# reading of where along the orbit the error is made.
#
# ## The claims at a glance
#
# One line per claim.  Each "where" links to that place in the report in
# brief (`website/report.md`: the report's equations, figures and claims by
# its own numbers), each "measured in" to the notebook section that
# measures it.

# %%
links = dict(root="../", html=True)  # the way from notebooks/ to the root
display(HTML(claims.table_html(claims.with_links(claims.glance(table), **links),
                               raw=("where", "measured in"))))

# %% [markdown]
# ## What was measured, and why each verdict
#
# The numbers behind each verdict and the reasoning, claim by claim (one
# click opens them; the paper's Table 3 holds the same):

# %%
detail = table[["claim", "measured", "verdict"]].rename(columns={"verdict": "why this verdict"})
display(HTML(claims.folded(claims.table_html(detail),
                           f"The measurements and the verdicts, {len(detail)} claims")))

# %% [markdown]
# ## Errata
#
# Each line is checked against the report's own derivation, with the
# evidence computed here or in the notebook named.  The first item
# measures what eq. 9 as printed would compute: setting $c_{i+1} = F$
# makes the spline's second derivative $2c = 2F$, i.e. it solves
# $y'' = 2F$.  The report's eqs. 16-18 were checked too: they agree with
# the derivative of Euler's equations (`tests/test_problems.py`), so they
# are not in the table.

# %%
crossing = claims.eq9_first_zero(h=0.01)  # y'' = -y solved as y'' = -2y: first zero, pi/2 expected
print(f"first zero at t = {crossing:.3f}")

# %%
errata = claims.errata_table(measured, crossing)
outputs.save_data(errata, "errata")
display(HTML(claims.table_html(claims.with_links(errata, **links), raw=("where",))))

# %% [markdown]
# ## How the tables are made
#
# Each claim is one function of `scripts/claims.py`, which reads the
# measurements (`data/*.csv`) and returns the verdict; the tables are
# written to `data/claims.csv` and `data/errata.csv`, and `make reproduce`
# copies the claims into the README.  The paper (`paper/splinestep.typ`)
# states a few of these numbers in its prose; they are written with the
# text it prints to `data/headline-numbers.csv`.

# %%
headline = claims.headline_numbers(measured)
outputs.save_data(headline, "headline-numbers")

# %% [markdown]
# ## Where to read on
#
# * The paper, `paper/splinestep.pdf`, states these verdicts with the
#   figures that support them, and Table 3 holds the measurements.
# * The user guide, `website/guide.md`, solves equations of your own with
#   the package: fixed and adaptive steps, events, boundary value problems
#   and Newmark's family.
# * Each verdict's notebook is linked from its row above; `make reproduce`
#   reruns every one of them and rebuilds these tables.
