"""The HTML report: its pages (Jinja2 templates) and the pictures drawn from results' evidence."""
