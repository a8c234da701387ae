# The flat entry layer (api/pom_api.h) that libpomlab and python/pomlab use.
pom_add_test(test_api test_api.c)
target_link_libraries(test_api PRIVATE pom_api)
