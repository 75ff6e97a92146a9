"""thermocal.report"""
