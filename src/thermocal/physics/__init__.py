"""thermocal.physics"""
