"""thermocal.io"""
