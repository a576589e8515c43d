mimics battery status night
mimics battery resume night
