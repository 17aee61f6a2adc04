"""Interfaces to a PLC or supervisor: the Modbus TCP status server (RosettaCNC table, seed 004)."""
