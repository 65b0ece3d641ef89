"""Result files: CSV, the Dymola/OpenModelica ``.mat`` format and Parquet, chosen by the
extension (``formats.write``/``formats.read``).
"""
