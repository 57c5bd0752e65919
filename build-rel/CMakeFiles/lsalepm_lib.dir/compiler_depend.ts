# CMAKE generated file: DO NOT EDIT!
# Timestamp file for compiler generated dependencies management for lsalepm_lib.
