"""thermocal.statespace"""
