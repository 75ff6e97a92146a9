"""thermocal.multizone"""
