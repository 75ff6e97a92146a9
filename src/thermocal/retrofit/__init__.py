"""thermocal.retrofit"""
