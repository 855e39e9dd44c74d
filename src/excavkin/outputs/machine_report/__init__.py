"""A machine's spec sheet as one self-contained HTML file, for any machine family.

The core lays out what a family wing computes: the wing turns its analyses into sections
(tables of values, named limits, charts citing their standards) and hands them over,
here as section sources built one after another with progress
([`collect`][excavkin.outputs.machine_report.content.collect]). The report draws what it is
given and never solves; it imports no wing.

* `content` — what a report holds (values with units, tables, charts, sections);
* `document` — the template filled, the file written (atomically, never over a file unless
  asked);
* `parts` — what every family's report shares: values in the sheet's units, binding limits
  named, the cylinders' table, the moving front, the report itself (`family_report`).

>>> from excavkin.outputs.machine_report import MachineReport, Section, Table, Value
>>> report = MachineReport(
...     "demo",
...     "a machine",
...     "",
...     (("mass", Value(1800.0, "mass", "kg", key="mass")),),
...     (Section("size", "Size", tables=(Table("Size", ("figure", "mm"),
...         (("reach", Value(1.25, "length", "mm", key="reach")),)),)),),
... )
>>> from excavkin.outputs.machine_report import build_machine_report
>>> 'data-key="reach" data-si="1.25"' in build_machine_report(report)
True
"""

from excavkin.outputs.machine_report.content import (
    Cell,
    Chart,
    MachineReport,
    Progress,
    Section,
    SectionSource,
    Table,
    Value,
    collect,
)
from excavkin.outputs.machine_report.document import (
    HTML_SUFFIXES,
    build_machine_report,
    write_machine_report,
)
from excavkin.outputs.machine_report.parts import (
    family_report,
    kg_value,
    kn_value,
    limit_name,
    mm_value,
)

__all__ = [
    "HTML_SUFFIXES",
    "Cell",
    "Chart",
    "MachineReport",
    "Progress",
    "Section",
    "SectionSource",
    "Table",
    "Value",
    "build_machine_report",
    "collect",
    "family_report",
    "kg_value",
    "kn_value",
    "limit_name",
    "mm_value",
    "write_machine_report",
]
