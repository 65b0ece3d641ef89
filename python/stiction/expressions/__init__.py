"""The expression language: Modelica expressions as parameters, derived variables and the
``.mo`` importer write them (``lexer`` → ``parser`` → ``ast`` → ``evaluate``).

The lowest layer above ``errors``: it imports nothing else of stiction.
"""
