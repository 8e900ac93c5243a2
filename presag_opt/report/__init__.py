"""The design report of a line: :func:`~presag_opt.report.content.design_report` computes it,
:func:`~presag_opt.report.html.write_report` writes it as one self-contained HTML file
(``presag report``)."""
