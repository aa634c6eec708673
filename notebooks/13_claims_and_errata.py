# %% [markdown]
# # The report's claims against what we measure, and its errata
#
# Every number in the two tables below is read from the data the earlier
# notebooks wrote (`data/*.csv`) or computed with the package; none is
# typed.  The tables are written to `data/claims.csv` and `data/errata.csv`,
# and `make reproduce` copies them into the README.

# %%
import inspect
import sys

from IPython.display import HTML, display

sys.path.insert(0, "../scripts")  # outputs.py: data/ and figures/; claims.py: these tables
import claims
import outputs

# %% [markdown]
# Each claim is one function of `scripts/claims.py`: it reads what the
# notebooks measured from `data/`, and returns where the report makes the
# claim, what it says, what was measured, the verdict and the notebook
# section that measures it.  `claims.CLAIMS` lists the functions in the
# table's order; here is one of them, the report's central claim:

# %%
print(inspect.getsource(claims.second_order))

# %%
measured = claims.Measured()  # data/*.csv, each read once
table = claims.claims_table(measured)
outputs.save_data(table, "claims")

# %% [markdown]
# ## The verdicts at a glance
#
# One line per claim: where the report makes it, what it says, the verdict and
# the notebook section that measures it.  *Reproduced*, *partly* and *not
# reproduced* judge what the report claims; *built* and *proved* answer what it
# suggests (a method built and measured, a proof); *beyond the report* marks
# findings it does not make.  What was measured, and each verdict in full, are
# in the second table (click to open it) and in `data/claims.csv`.  Each
# "where" links to that place in the report in brief (`website/report.md`:
# the report's equations, figures and claims by its own numbers).

# %%
links = dict(root="../", html=True)  # the way from notebooks/ to the root
glance = claims.with_links(claims.glance(table), **links)
display(HTML(claims.table_html(glance, raw=("where", "measured in"))))

# %%
full = claims.with_links(table[["where", "claim", "measured", "verdict"]], **links)
display(HTML("<details><summary><b>What was measured, and the verdicts in full</b></summary>"
             + claims.table_html(full, raw=("where",)) + "</details>"))

# %% [markdown]
# The few numbers the paper (`paper/splinestep.typ`) states in its prose, each
# with the text it prints, from the files above.

# %%
headline = claims.headline_numbers(measured)
outputs.save_data(headline, "headline-numbers")
print(headline[["name", "text"]].to_string(index=False))  # values: data/headline-numbers.csv

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
