"""Report: one result model rendered as plain text, rich tables, or JSON."""
