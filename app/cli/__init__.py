"""The command line: jacobian-lab serve, export, handout, record."""
